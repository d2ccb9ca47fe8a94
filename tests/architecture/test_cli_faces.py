"""One way in (issue 38): the command line reaches the other rooms only through their faces, the
names a room's package (or one of its sub-package faces) lists in `__all__`, as a script does
(docs/api.md). What a command prints is what those calls return; a module of the room beneath its
face is the room's own, free to change without a command noticing.

FACES is the whole list of modules cli/ may import from another room: each is a package, and
only the names in its `__all__` may be taken from it."""
from __future__ import annotations

import ast
import importlib
from pathlib import Path

ROOT = Path(__file__).parents[2]
ROOMS = ("store", "ingest", "reasoner", "explain", "sim_replay")
FACES = ("store", "store.wire", "store.cache", "store.keys", "store.transfer",  # the evidence, and its sub-faces
         "reasoner", "reasoner.regress", "reasoner.history",              # the judge's, and its parts'
         "explain", "ingest", "sim_replay")


def faces() -> set[str]:
    """The FACES that are made: a package's __init__ listing what it shows. A sub-face named
    above that is not a package yet (store's are being made beside this test) is no way in."""
    made = set()
    for face in FACES:
        try:
            module = importlib.import_module(face)
        except ModuleNotFoundError:
            continue
        if Path(module.__file__ or "").name == "__init__.py" and hasattr(module, "__all__"):
            made.add(face)
    return made


def imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """Every absolute import of another room in one file: (line, module, names taken from it)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.append((node.lineno, node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name, []) for a in node.names]
    return [(line, module, names) for line, module, names in found if module.split(".")[0] in ROOMS]


def breaches(path: Path) -> list[str]:
    """What in one cli/ file goes past a face, as `file:line what`."""
    out, made = [], faces()
    for line, module, names in imports(path):
        where = f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.name}:{line}"
        if module not in made:
            out.append(f"{where} imports {module}, not a face")
            continue
        shown = getattr(importlib.import_module(module), "__all__", [])
        out += [f"{where} imports {module}.{name}, not in {module}.__all__" for name in names if name not in shown]
    return out


def test_cli_imports_only_the_faces_of_other_rooms():
    files = sorted((ROOT / "cli").glob("*.py"))
    assert len(files) > 20
    assert [b for path in files for b in breaches(path)] == []


def test_every_room_shows_a_face():
    assert set(ROOMS) <= faces()
    for face in faces():
        module = importlib.import_module(face)
        assert all(hasattr(module, name) for name in module.__all__), face


def test_the_check_sees_a_way_past_the_faces(tmp_path):
    sample = tmp_path / "x.py"
    sample.write_text("from reasoner.investigation import Investigation\nfrom reasoner import Case, scene\n"
                      "import explain.report\nfrom explain import explanation\nimport typer\n"
                      "def f():\n    from sim_replay.paper import paper_run\n")
    assert [b.split(" ", 1)[1] for b in breaches(sample)] == [
        "imports reasoner.investigation, not a face", "imports reasoner.scene, not in reasoner.__all__",
        "imports explain.report, not a face", "imports sim_replay.paper, not a face"]
