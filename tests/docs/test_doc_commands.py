"""Every `$ gaps ...` example of README.md and docs/*.md runs, and prints what the docs show
(issue 39: the README tour, its counts and docs/regress.md's had drifted from what gaps prints).

A ```text (or ```sh, ```console) block with lines starting `$ ` is a session: each `$ gaps ...`
line runs in-process as a user types it, and what it prints (stdout and stderr, as a terminal
shows them) must match the lines below it up to the next `$ `. In the expected lines `…` stands for
any text, and a line that is only `…` for any number of lines. `$ echo $?` prints the exit code of
the command before; other shell lines (`cat`, `head`) run in bash. Each document has its own
folder, kept from block to block in document order, holding `gaps.db` with the paper's run
`paper-junctions` (the events `gaps demo --paper` publishes, appended directly; the README's tour
starts without it, as it says, and makes it with `gaps demo --paper`), the repository's
`reasoner/` and `tests/` (linked, for the paths the docs give), and every block fenced as
```text file=NAME written to NAME; a file a session shows with `$ cat NAME` is made with what it
shows, where no earlier step made it. A ```sh block without `$ ` is a list of commands: each `gaps`
line must run and exit 0.

A block that cannot run here says why on its fence: ```text no-run: <reason> (a long-running
service, a 10-minute simulation, a machine's /etc). A document's blocks run in one test, in order,
so that pytest-xdist never splits a session between workers.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest
from typer.testing import CliRunner

ROOT = Path(__file__).resolve().parents[2]
SESSION_LANGUAGES = {"text", "sh", "console"}
COLUMNS = 110


@dataclass(frozen=True)
class Fence:
    path: Path
    line: int
    language: str
    info: str
    lines: tuple[str, ...]

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"

    @property
    def no_run(self) -> str | None:
        found = re.search(r"\bno-run:\s*(.+)", self.info)
        return found[1].strip() if found else None

    @property
    def file(self) -> str | None:
        found = re.search(r"\bfile=(\S+)", self.info)
        return found[1] if found else None

    @property
    def is_session(self) -> bool:
        return any(line.startswith("$ ") for line in self.lines)

    @property
    def commands(self) -> list[str]:
        return [line.strip() for line in self.lines if line.strip().startswith("gaps ")]


def fences(path: Path) -> list[Fence]:
    found, lines, i = [], path.read_text(encoding="utf-8").splitlines(), 0
    while i < len(lines):
        if lines[i].startswith("```"):
            words = lines[i][3:].split(maxsplit=1)
            end = next(j for j in range(i + 1, len(lines)) if lines[j].strip() == "```")
            found.append(Fence(path, i + 1, words[0] if words else "", words[1] if len(words) > 1 else "",
                               tuple(lines[i + 1:end])))
            i = end
        i += 1
    return found


def documents() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def examples() -> list[Fence]:
    return [f for doc in documents() for f in fences(doc)
            if f.language in SESSION_LANGUAGES and not f.file and (f.is_session or f.language == "sh" and f.commands)]


def steps(fence: Fence) -> list[tuple[str, list[str]]]:
    """(command, the lines it is shown to print) in order."""
    out: list[tuple[str, list[str]]] = []
    for line in fence.lines:
        if line.startswith("$ "):
            out.append((line[2:], []))
        elif out:
            out[-1][1].append(line)
    return out


def matches(expected: list[str], actual: list[str]) -> bool:
    """Whether the printed lines are the shown ones, `…` standing for any text (a line of its own:
    any lines)."""
    exp = [e.rstrip() for e in expected]
    act = [a.rstrip() for a in actual]
    while exp and not exp[-1]:
        exp.pop()
    while act and not act[-1]:
        act.pop()
    memo: dict[tuple[int, int], bool] = {}

    def go(i: int, j: int) -> bool:
        if (i, j) in memo:
            return memo[(i, j)]
        if i == len(exp):
            ok = j == len(act)
        elif exp[i].strip() == "…":
            ok = any(go(i + 1, k) for k in range(j, len(act) + 1))
        else:
            ok = j < len(act) and _line(exp[i], act[j]) and go(i + 1, j + 1)
        memo[(i, j)] = ok
        return ok
    return go(0, 0)


def _line(expected: str, actual: str) -> bool:
    pattern = ".*".join(re.escape(part) for part in expected.split("…"))
    return re.fullmatch(pattern, actual) is not None


def make_folder(doc: Path, here: Path) -> Path:
    from sim_replay.paper import paper_run
    from store import Store
    if doc.name != "README.md":         # the README's tour starts in an empty folder
        with Store(here / "gaps.db") as store:
            store.append(paper_run())
    for name in ("reasoner", "tests"):
        (here / name).symlink_to(ROOT / name, target_is_directory=True)
    for fence in fences(doc):
        if fence.file:
            (here / fence.file).write_text("\n".join(fence.lines) + "\n", encoding="utf-8")
    return here


def run_gaps(line: str) -> tuple[int, list[str]]:
    from cli.main import app
    args = shlex.split(line, comments=True)[1:]
    result = CliRunner().invoke(app, args, env={"COLUMNS": str(COLUMNS), "GAPS_DB": None, "NO_COLOR": "1"},
                                prog_name="gaps")
    assert "Traceback" not in result.output, result.output
    return result.exit_code, result.output.splitlines()


def run_fence(fence: Fence, here: Path) -> list[str]:
    """What differs from the docs in this block (nothing: it runs as shown)."""
    if not fence.is_session:
        for line in fence.commands:
            code, printed = run_gaps(line)
            if code != 0:
                return [f"{fence.where}: `{line}` exited {code}:\n" + "\n".join(printed)]
        return []
    last = 0
    for command, shown in steps(fence):
        if command.strip() == "echo $?":
            printed = [str(last)]
        elif command.startswith("gaps "):
            last, printed = run_gaps(command)
        elif command.startswith("cat ") and not (here / command[4:].strip()).exists():
            (here / command[4:].strip()).write_text("\n".join(shown) + "\n", encoding="utf-8")   # the file shown
            last, printed = 0, shown
        else:
            done = subprocess.run(["bash", "-c", command], capture_output=True, text=True, cwd=here, timeout=60,
                                  env={**os.environ, "COLUMNS": str(COLUMNS)})
            last, printed = done.returncode, (done.stdout + done.stderr).splitlines()
        if not matches(shown, printed):
            return [f"{fence.where}: `$ {command}` printed\n" + "\n".join(printed)
                    + "\n--- the docs show ---\n" + "\n".join(shown)]
    return []


DOCS = sorted({f.path for f in examples()}, key=documents().index)


@pytest.mark.parametrize("doc", DOCS, ids=lambda d: str(d.relative_to(ROOT)))
def test_the_examples_of_a_document_run_as_shown(doc: Path, tmp_path, monkeypatch) -> None:
    """One test per document, its blocks in order in one folder (a later block uses what an
    earlier one made; pytest-xdist must not split them), every difference reported."""
    here = make_folder(doc, tmp_path)
    monkeypatch.chdir(here)
    wrong = [said for fence in examples() if fence.path == doc and not fence.no_run for said in run_fence(fence, here)]
    assert not wrong, "\n\n".join(wrong)


def test_a_block_that_does_not_run_says_why_and_is_rare():
    skipped = [f for f in examples() if f.no_run is not None]
    assert all(len(f.no_run) > 20 for f in skipped), [f.where for f in skipped]
    assert len(skipped) <= 15, [f.where for f in skipped]     # raise only with a reason on each fence


def test_the_matcher():
    assert matches(["a …", "…", "z"], ["a b c", "x", "y", "z"])
    assert matches(["a", "…"], ["a"])
    assert not matches(["a", "b"], ["a", "c"])
    assert not matches(["a"], ["a", "b"])
    assert matches(["head 3ac…"], ["head 3ac32"])
