"""The store's walls: no room outside store/ runs SQL on the store's tables or reaches into one of
its submodules; they use `import store` / `from store import X` with X in store.__all__.

bench/ is outside the walls on purpose: its benchmarks time the store's internals (the chain,
the snapshots, raw SQL alternatives) against each other, which is what they are for."""
import ast
import re
from pathlib import Path

import store

ROOT = Path(__file__).parents[2]
INSIDE = {"store", "tests", "bench", ".venv", ".git"}
TABLES = ("events", "quarantine", "checkpoints", "rulebooks", "legacy_checkpoints", "schema_version",
          "state_snapshots", "state_watermarks", "verifications", "liveliness", "wire_misses", "wire_checkpoints",
          "wire_legacy", "presence_marks", "cache_key")
SQL = re.compile(r"\b(SELECT|INSERT|UPDATE|DELETE|CREATE|DROP|ALTER)\b[\s\S]*\b(" + "|".join(TABLES) + r")\b")


def outside_files() -> list[Path]:
    return [path for path in ROOT.rglob("*.py") if path.relative_to(ROOT).parts[0] not in INSIDE]


def breaches(path: Path) -> list[str]:
    """What in one file goes through the store's walls, as `file:line what`."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        where = f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.startswith("store."):
                found.append(f"{where} imports {node.module}")
            elif node.module == "store":
                found += [f"{where} imports store.{a.name}, not in store.__all__"
                          for a in node.names if a.name not in store.__all__]
        elif isinstance(node, ast.Import):
            found += [f"{where} imports {a.name}" for a in node.names if a.name.startswith("store.")]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and SQL.search(node.value):
            found.append(f"{where} holds SQL: {node.value[:60]!r}")
    return found


def test_no_room_goes_through_the_stores_walls():
    files = outside_files()
    assert {p.relative_to(ROOT).parts[0] for p in files} >= {"reasoner", "explain", "cli", "ingest", "sim_replay"}
    assert [b for path in files for b in breaches(path)] == []


def test_the_check_sees_a_breach(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    sample = tmp_path / "reasoner" / "x.py"
    sample.parent.mkdir()
    sample.write_text('from store.state import state_at\nfrom store import snapshots, Store\nimport store.kinds\n'
                      'q = "SELECT t FROM events WHERE run = ?"\n')
    assert [b.split(" ", 1)[1] for b in breaches(sample)] == [
        "imports store.state", "imports store.snapshots, not in store.__all__", "imports store.kinds",
        "holds SQL: 'SELECT t FROM events WHERE run = ?'"]


def test_everything_the_store_exports_exists():
    assert all(hasattr(store, name) for name in store.__all__)


# Explain renders, the reasoner reasons (DESIGN): explain and cli read the reasoner's face
# (reasoner.wording for the rulebooks' English; a rulebook a user wrote through `reasoner`'s own face),
# never the LE compiler's modules, which are the reasoner's own part.
COMPILER = "reasoner.le"
FACE_ONLY = ("explain", "cli")


def _is_compiler(module: str) -> bool:
    return module == COMPILER or module.startswith(COMPILER + ".")


def compiler_imports(path: Path) -> list[str]:
    """Where one file imports the LE compiler, as `file:line what`."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        where = f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if _is_compiler(node.module):
                found.append(f"{where} imports {node.module}")
            elif node.module == "reasoner":
                found += [f"{where} imports reasoner.{a.name}" for a in node.names if a.name == "le"]
        elif isinstance(node, ast.Import):
            found += [f"{where} imports {a.name}" for a in node.names if _is_compiler(a.name)]
    return found


def test_explain_and_cli_never_import_the_le_compiler():
    files = [path for room in FACE_ONLY for path in (ROOT / room).rglob("*.py")]
    assert {p.relative_to(ROOT).parts[0] for p in files} == set(FACE_ONLY)
    assert [b for path in files for b in compiler_imports(path)] == []


def test_the_check_sees_a_compiler_import(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    sample = tmp_path / "explain" / "x.py"
    sample.parent.mkdir()
    sample.write_text("from reasoner.le.render import arg_text\nfrom reasoner import le, model\nimport reasoner.le\n"
                      "import reasoner.legal\nfrom reasoner.wording import arg_text\nfrom reasoner import lexicon\n")
    assert [b.split(" ", 1)[1] for b in compiler_imports(sample)] == [
        "imports reasoner.le.render", "imports reasoner.le", "imports reasoner.le"]
