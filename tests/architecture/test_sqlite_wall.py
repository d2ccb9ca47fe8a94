"""One error wall: only the store speaks SQLite. No module outside store/ imports sqlite3 or names
its errors; what SQLite says of the file reaches the other rooms as the store's own errors
(store/errors.py: StoreFault and its kinds, translated in store/sqlite_errors.py).

bench/ is outside the walls on purpose, as for test_walls.py: it prints SQLite's version beside
its figures."""
from __future__ import annotations

import ast
import sys
from pathlib import Path

from store.errors import DiskFailed, DiskFull, GapsError, RowRefused, StoreBusy, StoreDamaged, StoreFault, StoreReadOnly
from tests.architecture.test_walls import ROOT, outside_files


def sqlite_uses(path: Path) -> list[str]:
    """Each import of sqlite3 (or its C module) and each use of a name from it, as `file:line what`."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        where = f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.Import):
            found += [f"{where} imports {a.name}" for a in node.names if a.name.split(".")[0] in ("sqlite3", "_sqlite3")]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").split(".")[0] in (
                "sqlite3", "_sqlite3"):
            found.append(f"{where} imports from {node.module}")
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "sqlite3":
            found.append(f"{where} uses sqlite3.{node.attr}")
    return found


def test_no_room_but_the_store_speaks_sqlite():
    files = outside_files()
    assert {p.relative_to(ROOT).parts[0] for p in files} >= {"reasoner", "explain", "cli", "ingest", "sim_replay"}
    assert [use for path in files for use in sqlite_uses(path)] == []


def test_the_check_sees_sqlite(tmp_path, monkeypatch):
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    sample = tmp_path / "cli" / "x.py"
    sample.parent.mkdir()
    sample.write_text("import sqlite3\nfrom sqlite3 import OperationalError\ntry:\n    pass\n"
                      "except sqlite3.DatabaseError:\n    pass\n")
    assert [u.split(" ", 1)[1] for u in sqlite_uses(sample)] == [
        "imports sqlite3", "imports from sqlite3", "uses sqlite3.DatabaseError"]


def test_the_stores_errors_are_the_projects():
    """Each kind is a StoreFault, a GapsError: one `except` catches them; exit 1 as a damaged file."""
    for kind in (StoreDamaged, StoreBusy, StoreReadOnly, DiskFull, DiskFailed, RowRefused):
        assert issubclass(kind, StoreFault) and issubclass(kind, GapsError) and kind.exit_code == 1
