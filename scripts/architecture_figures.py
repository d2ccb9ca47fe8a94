"""The architecture's figures, before and after a restructuring (issue 38): how deep a `gaps`
command walks through the rooms, the biggest modules and classes, modules per folder, what each
room shows its callers, and the type checker's errors per room.

    .venv/bin/python scripts/architecture_figures.py [--json] [--no-mypy] [--no-walks] [--stacks]

The walks are measured, not read from the source: each command runs in-process on the paper's
run (a temporary store), under a profile hook that records every stack of the project's own
frames; the longest is printed with the rooms it passes through in order ("cli > reasoner >
store > reasoner" is three changes of room), and the calls from one room into another counted.
Its "layers" count each function once however often it recurses (a comprehension is its
function's): of a stack that walks a proof tree's nesting, only the walk's own frames are layers.
`--stacks` also prints the frames (file and function) of the deepest stack and of the one with
the most layers, to see what they pass through.
The sizes are read with `ast`. The type checker is mypy (default settings, missing imports
ignored) where it is installed; without it the row says so.
"""
from __future__ import annotations

import argparse
import ast
import json
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
ROOMS = ("store", "ingest", "reasoner", "explain", "sim_replay", "cli")
COMMANDS = (
    ["runs", "--json"],
    ["incidents", "--run", "paper-junctions", "--json"],
    ["explain", "--run", "paper-junctions", "1"],
    ["scene", "--run", "paper-junctions", "--at", "10s", "--vehicle", "173", "--json"],
    ["verify", "--json"],
    ["report", "--run", "paper-junctions", "-o", "{tmp}/r.html"],
)


# --- sizes ------------------------------------------------------------------------------------

def modules(room: str) -> list[Path]:
    return sorted(p for p in (ROOT / room).rglob("*.py") if "__pycache__" not in p.parts)


def sizes() -> dict[str, Any]:
    per_folder: Counter[str] = Counter()
    mods, classes = [], []
    for room in ROOMS:
        for path in modules(room):
            rel = path.relative_to(ROOT)
            per_folder[str(rel.parent)] += 1
            text = path.read_text(encoding="utf-8")
            mods.append((len(text.splitlines()), str(rel)))
            for node in ast.walk(ast.parse(text)):
                if isinstance(node, ast.ClassDef):
                    classes.append(((node.end_lineno or node.lineno) - node.lineno + 1, f"{rel}:{node.name}"))
    return {"modules_per_folder": dict(sorted(per_folder.items())),
            "biggest_modules": sorted(mods, reverse=True)[:5],
            "biggest_classes": sorted(classes, reverse=True)[:5]}


def faces() -> dict[str, list[str]]:
    """What each room's package and each of its sub-packages shows (keyed by folder): its `__all__`,
    else the names its __init__ binds without a leading underscore."""
    out = {}
    folders = [f"{room}/{p.parent.relative_to(ROOT / room).as_posix()}" for room in ROOMS
               for p in sorted((ROOT / room).rglob("*/__init__.py")) if "__pycache__" not in p.parts]
    for room in [*ROOMS, *folders]:
        init = ROOT / room / "__init__.py"
        tree = ast.parse(init.read_text(encoding="utf-8")) if init.exists() else ast.Module(body=[], type_ignores=[])
        names: list[str] = []
        for node in tree.body:
            if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
                names = [ast.literal_eval(e) for e in node.value.elts]  # type: ignore[attr-defined]
                break
            if isinstance(node, (ast.ImportFrom, ast.Import)):
                names += [a.asname or a.name for a in node.names]
            elif isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                names.append(node.name)
        out[room] = sorted(n for n in set(names) if not n.startswith("_") and n != "annotations")
    return out


# --- the type checker ----------------------------------------------------------------------------

def mypy_errors() -> dict[str, int] | str:
    try:
        import mypy  # noqa: F401
    except ImportError:
        return "mypy is not installed"
    done = subprocess.run([sys.executable, "-m", "mypy", "--ignore-missing-imports", "--no-error-summary",
                           *ROOMS], cwd=ROOT, capture_output=True, text=True)
    counts: Counter[str] = Counter()
    for line in done.stdout.splitlines():
        if ": error:" in line:
            counts[line.split("/", 1)[0].split(":", 1)[0]] += 1
    return {room: counts.get(room, 0) for room in ROOMS}


# --- the walks -----------------------------------------------------------------------------------

def room_of(filename: str) -> str | None:
    try:
        rel = Path(filename).resolve().relative_to(ROOT)
    except ValueError:
        return None
    return rel.parts[0] if rel.parts and rel.parts[0] in ROOMS else None


def walk(argv: list[str], db: str) -> dict[str, Any]:
    """The deepest stack of the project's own frames while `gaps argv` runs, its rooms and its
    frames (`path:qualname`, outermost first)."""
    from typer.testing import CliRunner

    from cli.main import app

    deepest: list[tuple[str, Any]] = []
    widest: list[str] = []              # the stack passing through most changes of room
    stack: list[tuple[str, Any]] = []   # (room, code) of each of the project's frames
    crossings = 0                       # calls from one room into another
    on_stack: Counter[tuple[str, str]] = Counter()      # each function's frames on the stack
    layers = 0
    layered: list[tuple[str, Any]] = []     # the stack with the most layers

    def hook(frame: Any, event: str, _arg: Any) -> None:
        nonlocal deepest, widest, crossings, layers, layered
        if event == "call":
            room = room_of(frame.f_code.co_filename)
            if room is not None:
                crossings += bool(stack) and stack[-1][0] != room
                stack.append((room, frame.f_code))
                on_stack[layer(frame.f_code)] += 1
                if len(on_stack) > layers:
                    layers, layered = len(on_stack), list(stack)
                if len(stack) > len(deepest):
                    deepest = list(stack)
                if changes(r for r, _ in stack) > changes(widest):
                    widest = [r for r, _ in stack]
        elif event == "return" and stack and room_of(frame.f_code.co_filename) is not None:
            key = layer(stack.pop()[1])
            on_stack[key] -= 1
            if not on_stack[key]:
                del on_stack[key]

    CliRunner().invoke(app, argv)       # once unwatched: the rulebooks compiled and kept (the LE reader's
    for kept in Path(db).parent.glob(Path(db).name + ".cache*"):   # time bound is wall clock, which the
        kept.unlink()                   # hook would eat); the judgement kept beside the store let go
    sys.setprofile(hook)
    try:
        result = CliRunner().invoke(app, argv)
    finally:
        sys.setprofile(None)
    if result.exit_code != 0:
        print(f"gaps {' '.join(argv)}: exit {result.exit_code}: {result.output[-400:]}", file=sys.stderr)
    return {"command": "gaps " + " ".join(argv), "exit": result.exit_code, "depth": len(deepest), "layers": layers,
            "deepest_rooms": " > ".join(collapsed(r for r, _ in deepest)), "widest_rooms": " > ".join(collapsed(widest)),
            "changes_of_room": changes(widest), "crossings": crossings,
            "deepest_stack": frames(deepest), "most_layers_stack": frames(layered)}


def frames(stack: list[tuple[str, Any]]) -> list[str]:
    return [f"{where(code.co_filename)}:{code.co_qualname}" for _, code in stack]


def where(filename: str) -> str:
    return Path(filename).resolve().relative_to(ROOT).as_posix()


COMPREHENSIONS = (".<listcomp>", ".<dictcomp>", ".<setcomp>", ".<genexpr>")


def layer(code: Any) -> tuple[str, str]:
    """The function a frame belongs to: a comprehension's is the function it is written in."""
    name = code.co_qualname
    for suffix in COMPREHENSIONS:
        if name.endswith(suffix):
            name = name[:-len(suffix)].removesuffix(".<locals>")
            break
    return code.co_filename, name


def collapsed(rooms: Any) -> list[str]:
    out: list[str] = []
    for room in rooms:
        if not out or out[-1] != room:
            out.append(room)
    return out


def changes(rooms: Any) -> int:
    return max(len(collapsed(rooms)) - 1, 0)


def walks() -> list[dict[str, Any]]:
    sys.path.insert(0, str(ROOT))
    from sim_replay.paper import paper_run
    from store import Store

    with tempfile.TemporaryDirectory() as tmp:
        db = Path(tmp) / "gaps.db"
        with Store(db) as store:
            store.append(paper_run())
        return [walk([*(a.format(tmp=tmp) for a in argv), "--db", str(db)], str(db)) for argv in COMMANDS]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--no-mypy", action="store_true")
    ap.add_argument("--no-walks", action="store_true")
    ap.add_argument("--stacks", action="store_true", help="print each walk's deepest stack, frame by frame")
    args = ap.parse_args()
    figures: dict[str, Any] = {**sizes(), "faces": faces()}
    if not args.no_mypy:
        figures["mypy_errors"] = mypy_errors()
    if not args.no_walks:
        figures["walks"] = walks()
        if not args.stacks:
            for w in figures["walks"]:
                del w["deepest_stack"], w["most_layers_stack"]
    if args.json:
        print(json.dumps(figures, indent=1))
        return 0
    print("modules per folder:", ", ".join(f"{k} {v}" for k, v in figures["modules_per_folder"].items()))
    print("biggest modules:", "; ".join(f"{p} ({n} lines)" for n, p in figures["biggest_modules"]))
    print("biggest classes:", "; ".join(f"{p} ({n} lines)" for n, p in figures["biggest_classes"]))
    for room, names in figures["faces"].items():
        print(f"{room}'s face: {len(names)} names")
    if "mypy_errors" in figures:
        m = figures["mypy_errors"]
        print("mypy errors:", m if isinstance(m, str) else ", ".join(f"{k} {v}" for k, v in m.items())
              + f" (total {sum(m.values())})")
    for w in figures.get("walks", []):
        print(f"{w['command']}: exit {w['exit']}, deepest stack {w['depth']} frames, {w['layers']} layers "
              f"({w['deepest_rooms']}); "
              f"most rooms on one stack {w['widest_rooms']} ({w['changes_of_room']} changes); "
              f"{w['crossings']:,} calls from one room into another")
        for title, key in (("deepest stack", "deepest_stack"), ("the stack with most layers", "most_layers_stack")):
            if key in w:
                print(f"  {title}:")
                for depth, frame in enumerate(w[key], 1):
                    print(f"  {depth:3} {frame}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
