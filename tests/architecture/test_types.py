"""The type checker's ratchet: mypy (pinned in pyproject.toml) over every room, one run for the suite.

The rooms and folders listed as clean in type_counts.json must have no error at all; every other room keeps
the count recorded there, which may only go down. A count that rises fails (fix the new error, don't raise
the file); a count that falls also fails, asking for the file to be lowered, so the ratchet holds what was
won. Each error is charged to the longest clean or counted path that holds its file (reasoner/le/... to
reasoner/le, the rest of reasoner/ to reasoner); a file under no listed path counts as clean.

One test, so that pytest-xdist runs mypy once, in one worker; its cache lives in the checkout's .mypy_cache
(a cold run costs ~12 s of CPU, 13-60 s of wall time on a busy two-core machine; a warm one ~2-3 s). After a merge or a fix, regenerate the
counts with

    .venv/bin/python tests/architecture/test_types.py --update

which writes the present count of every counted room (one with none left becomes clean; clean paths stay as
they are) and prints the file.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COUNTS = Path(__file__).with_name("type_counts.json")
# "path/to/file.py:12: error: ..." or "path/to/file.py: error: ..." (a file-level error has no line)
ERROR = re.compile(r"^(?P<path>[^\s:]+\.pyi?):(?:\d+:)*\s*error:")


def run_mypy() -> list[str]:
    """mypy's error lines over the files [tool.mypy] names, run from the checkout with its cache there."""
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(ROOT / ".mypy_cache"), "--no-color-output",
         "--no-error-summary"],
        cwd=ROOT, capture_output=True, text=True, check=False)
    if done.returncode not in (0, 1):  # 2: mypy itself failed (bad config, crash), not a type error
        raise RuntimeError(f"mypy exited {done.returncode}:\n{done.stdout}\n{done.stderr}")
    return [line for line in done.stdout.splitlines() if ERROR.match(line)]


def owner(path: str, places: list[str]) -> str:
    """The longest listed path that holds `path`; the file's top folder when none does."""
    held = [p for p in places if path == p or path.startswith(p.rstrip("/") + "/")]
    return max(held, key=len) if held else path.split("/", 1)[0]


def charged(errors: list[str], places: list[str]) -> list[tuple[str, str]]:
    """Each error line with the listed path (or unlisted top folder) it is charged to."""
    out = []
    for line in errors:
        match = ERROR.match(line)
        assert match is not None  # run_mypy kept only matching lines
        out.append((owner(match["path"], places), line))
    return out


def tally(errors: list[str], places: list[str]) -> Counter[str]:
    """How many errors each listed path (or unlisted top folder) holds."""
    return Counter(place for place, _ in charged(errors, places))


def load() -> tuple[list[str], dict[str, int]]:
    recorded = json.loads(COUNTS.read_text())
    return list(recorded["clean"]), dict(recorded["counts"])


def test_types_clean_rooms_stay_clean_and_counts_only_fall() -> None:
    clean, counts = load()
    errors = charged(run_mypy(), clean + list(counts))
    found = Counter(place for place, _ in errors)
    dirty = [line for place, line in errors if place not in counts]
    assert not dirty, (f"{len(dirty)} type error(s) where none is allowed (the clean paths {clean} and any "
                       "folder not counted in tests/architecture/type_counts.json):\n" + "\n".join(dirty))
    rose = {room: (counts[room], found[room]) for room in counts if found[room] > counts[room]}
    assert not rose, (f"type errors rose (room: recorded, now): {rose}; fix the new ones:\n"
                      + "\n".join(line for place, line in errors if place in rose))
    fell = {room: (counts[room], found[room]) for room in counts if found[room] < counts[room]}
    assert not fell, (f"type errors fell (room: recorded, now): {fell}; lower the file: "
                      ".venv/bin/python tests/architecture/test_types.py --update")


def update() -> None:
    """Write the present count of every counted room into type_counts.json; a room with none left joins
    the clean paths (which stay as listed)."""
    clean, counts = load()
    found = tally(run_mypy(), clean + list(counts))
    recorded = json.loads(COUNTS.read_text())
    recorded["clean"] = sorted({*clean, *(room for room in counts if not found[room])})   # none left: clean
    recorded["counts"] = {room: found[room] for room in sorted(counts) if found[room]}
    COUNTS.write_text(json.dumps(recorded, indent=2) + "\n")
    print(json.dumps(recorded, indent=2))
    unclean = {path: found[path] for path in clean if found[path]}
    if unclean:
        print(f"clean paths with errors (fix them; the test fails): {unclean}", file=sys.stderr)


if __name__ == "__main__":
    if sys.argv[1:] != ["--update"]:
        sys.exit("usage: python tests/architecture/test_types.py --update")
    update()
