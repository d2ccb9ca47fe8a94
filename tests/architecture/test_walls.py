"""The walls between rooms and around their parts: no room outside store/ runs SQL on the store's
tables; every part that shows a face (docs/design.md, "Rooms and their faces") is entered only
through it. Other rooms import the store as `store`, `store.wire`, `store.cache`, `store.keys`,
`store.transfer` or `store.errors`, each name in that face's `__all__`, never a module inside
(`store.db`, `store.chain`, `store.wire.contract`); the reasoner's history and regression are
entered as `reasoner.history` and `reasoner.regress`, by the rest of the reasoner too. The other
rooms import the reasoner only through its faces (REASONER_FACES below: its package, those two
sub-faces and a few module faces), each by the rooms the face is for, and only the names in its
`__all__`.

bench/ is outside the walls on purpose: its benchmarks time the store's internals (the chain,
the snapshots, raw SQL alternatives) against each other, which is what they are for; tests/ reach
inside to test the parts themselves, and scripts/ (one-off checks of the reasoner's figures) may
reach inside the reasoner."""
import ast
import importlib
import re
from pathlib import Path

import store

ROOT = Path(__file__).parents[2]
INSIDE = {"store", "tests", "bench", ".venv", ".git"}
FACES = ("store", "store.wire", "store.cache", "store.keys", "store.transfer", "store.errors", "store.run_map",
         "reasoner.history", "reasoner.regress")
TABLES = ("events", "quarantine", "checkpoints", "rulebooks", "legacy_checkpoints", "schema_version",
          "state_snapshots", "state_watermarks", "verifications", "liveliness", "wire_misses", "wire_checkpoints",
          "wire_legacy", "presence_marks", "cache_key")
SQL = re.compile(r"\b(SELECT|INSERT|UPDATE|DELETE|CREATE|DROP|ALTER)\b[\s\S]*\b(" + "|".join(TABLES) + r")\b")


def outside_files() -> list[Path]:
    return [path for path in ROOT.rglob("*.py") if path.relative_to(ROOT).parts[0] not in INSIDE]


def shown(face: str) -> set[str]:
    module = importlib.import_module(face)
    return set(getattr(module, "__all__", None) or (n for n in vars(module) if not n.startswith("_")))


def walled(module: str) -> str | None:
    """The face a module sits behind (the deepest face it is inside), or None if it is no face's."""
    behind = [face for face in FACES if module.startswith(face + ".")]
    return max(behind, key=len) if behind else None


def within(path: Path, face: str) -> bool:
    """Whether a file is part of what a face shows (its own modules use one another freely)."""
    owner = ("store",) if face.startswith("store") else tuple(face.split("."))
    return path.relative_to(ROOT).parts[:len(owner)] == owner


def absolute(path: Path, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    package = list(path.relative_to(ROOT).with_suffix("").parts)[:-1]
    base = package[:len(package) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def through_faces(path: Path, module: str, names: list[str], where: str) -> list[str]:
    """What one import takes from behind a face, or from a face beyond what it shows."""
    found = []
    if module in FACES and not within(path, module):
        for name in names:
            if f"{module}.{name}" in FACES:
                continue
            if name not in shown(module):
                found.append(f"{where} imports {module}.{name}, not in {module}.__all__")
    face = walled(module)
    if face and module not in FACES and not within(path, face):
        found.append(f"{where} imports {module}")
    return found


def breaches(path: Path) -> list[str]:
    """What in one file goes through a wall, as `file:line what`."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        where = f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.ImportFrom):
            found += through_faces(path, absolute(path, node), [a.name for a in node.names], where)
        elif isinstance(node, ast.Import):
            for a in node.names:
                found += through_faces(path, a.name, [], where)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and SQL.search(node.value):
            found.append(f"{where} holds SQL: {node.value[:60]!r}")
    return found


def test_no_room_goes_through_the_walls():
    files = outside_files()
    assert {p.relative_to(ROOT).parts[0] for p in files} >= {"reasoner", "explain", "cli", "ingest", "sim_replay"}
    assert [b for path in files for b in breaches(path)] == []


def test_the_check_sees_a_breach(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    sample = tmp_path / "explain" / "x.py"
    sample.parent.mkdir()
    sample.write_text('from store.state import state_at\nfrom store import snapshots, Store\nimport store.kinds\n'
                      'from store.wire import session_config, contract\nfrom store.wire.contract import MODES\n'
                      'from store import session_config\nimport store.db\n'
                      'from reasoner.history.motion import mph\nfrom reasoner.history import mph, read\n'
                      'from reasoner.regress import regress\nfrom reasoner.regress.text import lines\n'
                      'q = "SELECT t FROM events WHERE run = ?"\n')
    assert [b.split(" ", 1)[1] for b in breaches(sample)] == [
        "imports store.state", "imports store.snapshots, not in store.__all__", "imports store.kinds",
        "imports store.wire.contract, not in store.wire.__all__", "imports store.wire.contract",
        "imports store.session_config, not in store.__all__", "imports store.db",
        "imports reasoner.history.motion", "imports reasoner.history.read, not in reasoner.history.__all__",
        "imports reasoner.regress.text", "holds SQL: 'SELECT t FROM events WHERE run = ?'"]


def test_the_reasoners_own_modules_enter_its_parts_through_their_faces(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    (tmp_path / "reasoner" / "history").mkdir(parents=True)
    outside, inside = tmp_path / "reasoner" / "derived.py", tmp_path / "reasoner" / "history" / "others.py"
    text = "from .history.motion import mph\nfrom .history import Passage\nfrom . import history\n"
    outside.write_text(text)
    inside.write_text("from .motion import mph\nfrom ..history import Passage\nfrom ..when import format_time\n")
    assert [b.split(" ", 1)[1] for b in breaches(outside)] == ["imports reasoner.history.motion"]
    assert breaches(inside) == []


def test_every_face_hands_out_what_it_names():
    for face in FACES:
        module = importlib.import_module(face)
        assert all(hasattr(module, name) for name in shown(face)), face


def test_the_store_shows_a_small_core_face():
    # 125 names before issue 38; 46 after it (the core, the store's faults, the verify outcome and its parts)
    assert len(store.__all__) < 50


def reasoner_imports(path: Path) -> set[str]:
    """The reasoner's modules one file imports, by their names under reasoner/."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.ImportFrom):
            module = absolute(path, node)
            found |= ({module} if module != "reasoner" else {f"reasoner.{a.name}" for a in node.names})
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
    return {m for m in found if m.startswith("reasoner.")}


def test_the_history_leans_on_the_reasoners_leaves_only_and_only_the_api_calls_the_regression():
    """docs/design.md "Rooms and their faces": the history imports of the reasoner only model,
    vocabulary and when; the regression calls the judge, and of the reasoner only its API calls it."""
    history = sorted((ROOT / "reasoner" / "history").glob("*.py"))
    leaned = {m for path in history for m in reasoner_imports(path) if not m.startswith("reasoner.history")}
    assert history and leaned <= {"reasoner.model", "reasoner.vocabulary", "reasoner.when"}, leaned
    rest = [p for p in (ROOT / "reasoner").rglob("*.py")
            if "regress" not in p.relative_to(ROOT).parts and p != ROOT / "reasoner" / "api.py"]
    assert [str(p.relative_to(ROOT)) for p in rest
            if any(m.startswith("reasoner.regress") for m in reasoner_imports(p))] == []


# The reasoner's faces for the other rooms (docs/design.md, "Rooms and their faces"), each with the
# rooms that may import it: the package's face (the public API and the values its answers are made
# of), the sub-faces of its parts, and a few modules whose `__all__` hands out the part a room
# needs beyond the API: the incident's values, the verdict words, the core vocabulary's sentences,
# the times as explanations write them, the rulebooks' English, the scene and the timelines around
# a moment, an act's passage (for explain's renderings) and the law on board (for the simulation's
# agents, which ask the rulebooks live). A room takes from a face only what its `__all__` names,
# by import or by reading a face imported whole (`vocab.HAS_LIGHT`). The reasoner's own modules
# use one another freely (its parts through their faces, above); tests/, bench/ and scripts/ reach
# inside on purpose (they test, time and check the parts themselves) and are outside this rule.
REASONER_FACES = {
    "reasoner": ("cli", "explain", "sim_replay"),
    "reasoner.history": ("explain", "sim_replay"),
    "reasoner.regress": ("cli",),
    "reasoner.model": ("explain",),
    "reasoner.verdicts": ("explain",),
    "reasoner.vocabulary": ("explain", "sim_replay"),
    "reasoner.when": ("explain",),
    "reasoner.wording": ("explain",),
    "reasoner.scene": ("explain",),
    "reasoner.timelines": ("explain",),
    "reasoner.acts": ("explain",),
    "reasoner.onboard": ("sim_replay",),
}
ROOMS = ("cli", "explain", "ingest", "sim_replay")      # every room but the reasoner (store imports nothing of ours)


def _entered(room: str, face: str, where: str) -> list[str]:
    if face not in REASONER_FACES:
        return [f"{where} imports {face}, not a face of the reasoner"]
    if room not in REASONER_FACES[face]:
        return [f"{where} imports {face}, a face for {', '.join(REASONER_FACES[face])} only"]
    return []


def _taken(room: str, face: str, name: str, where: str, verb: str = "imports") -> tuple[list[str], str | None]:
    """One name taken from a face: what that breaks, and the face it is if it is one (else None)."""
    if f"{face}.{name}" in REASONER_FACES:
        return _entered(room, f"{face}.{name}", where), f"{face}.{name}"
    if name not in shown(face):
        return [f"{where} {verb} {face}.{name}, not in {face}.__all__"], None
    return [], None


def _chain(node: ast.Attribute) -> tuple[str, list[str]] | None:
    """`a.b.c` as ("a", ["b", "c"]); None for anything but names and attributes."""
    attrs: list[str] = []
    value: ast.expr = node
    while isinstance(value, ast.Attribute):
        attrs.insert(0, value.attr)
        value = value.value
    return (value.id, attrs) if isinstance(value, ast.Name) else None


def reasoner_breaches(path: Path) -> list[str]:
    """Where one file of a room goes past the reasoner's faces, as `file:line what`."""
    room, found, whole = path.relative_to(ROOT).parts[0], [], {}
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    for node in ast.walk(tree):
        where = f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").split(".")[0] == "reasoner":
            entered = _entered(room, node.module or "", where)
            found += entered
            for a in [] if entered else node.names:
                broken, face = _taken(room, node.module or "", a.name, where)
                found += broken
                if face:
                    whole[a.asname or a.name] = face
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "reasoner":
                    found += _entered(room, a.name, where)
                    whole[a.asname or "reasoner"] = a.name if a.asname else "reasoner"
    reads = [node for node in ast.walk(tree) if isinstance(node, ast.Attribute)]
    inner = {id(node.value) for node in reads}
    for node in reads:
        chain = _chain(node) if id(node) not in inner else None      # each whole `a.b.c` once
        if chain is None or chain[0] not in whole:
            continue
        face, where = whole[chain[0]], f"{path.relative_to(ROOT)}:{node.lineno}"
        for attr in chain[1]:
            broken, deeper = _taken(room, face, attr, where, "reads")
            found += broken
            if not deeper:
                break
            face = deeper
    return found


def test_other_rooms_enter_the_reasoner_through_its_faces():
    files = [path for room in ROOMS for path in sorted((ROOT / room).rglob("*.py"))]
    assert {p.relative_to(ROOT).parts[0] for p in files} == set(ROOMS)
    assert [b for path in files for b in reasoner_breaches(path)] == []


def test_the_check_sees_a_way_past_the_reasoners_faces(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    for room in ROOMS:
        (tmp_path / room).mkdir()
    sample = tmp_path / "explain" / "x.py"
    sample.write_text("from reasoner.investigation import Investigation\nfrom reasoner import Case, scene_parts, le\n"
                      "from reasoner.vocabulary import CAN, Template\nfrom reasoner import vocabulary as vocab\n"
                      "said = (vocab.HAS_LIGHT, vocab.STAGES)\nimport reasoner.le.sentences\n"
                      "from reasoner.onboard import get_engine\nimport reasoner\n"
                      "case = reasoner.open('x')\nreasoner.history.passage, reasoner.history.read\n"
                      "from reasoner.history import Passage\nfrom reasoner.scene import Scene, scene\n"
                      "def f():\n    from reasoner.engine import Rulebook\n")
    assert [b.split(" ", 1)[1] for b in reasoner_breaches(sample)] == [
        "imports reasoner.investigation, not a face of the reasoner",
        "imports reasoner.scene_parts, not in reasoner.__all__", "imports reasoner.le, not in reasoner.__all__",
        "imports reasoner.vocabulary.Template, not in reasoner.vocabulary.__all__",
        "imports reasoner.le.sentences, not a face of the reasoner", "imports reasoner.onboard, a face for sim_replay only",
        "imports reasoner.engine, not a face of the reasoner",
        "reads reasoner.vocabulary.STAGES, not in reasoner.vocabulary.__all__",
        "reads reasoner.history.read, not in reasoner.history.__all__"]
    elsewhere = {"sim_replay": "from reasoner.wording import term\nfrom reasoner.onboard import get_engine\n",
                 "ingest": "from reasoner import Case\n", "cli": "from reasoner.model import Incident\n"}
    for room, text in elsewhere.items():
        (tmp_path / room / "x.py").write_text(text)
    assert [b.split(" ", 1)[1] for room in elsewhere for b in reasoner_breaches(tmp_path / room / "x.py")] == [
        "imports reasoner.wording, a face for explain only", "imports reasoner, a face for cli, explain, sim_replay only",
        "imports reasoner.model, a face for explain only"]


def test_every_reasoner_face_hands_out_what_it_names():
    for face in REASONER_FACES:
        module = importlib.import_module(face)
        assert module.__all__ and all(hasattr(module, name) for name in module.__all__), face


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
