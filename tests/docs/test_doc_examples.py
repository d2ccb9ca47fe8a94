"""Every ```python block of README.md and docs/*.md runs against today's code, so an example in the
docs cannot quietly stop working (issue 11: docs/reasoner.md's example used an undefined name).

Each block runs alone, in a fresh namespace, in its own directory holding `gaps.db`: a store of the
demo's run `paper-junctions` (the events `gaps demo` publishes, appended directly, without Zenoh;
as a reader who ran `gaps demo --paper` has it), also named by $GAPS_DB. A block that cannot run here (it needs a browser, a network, a file of the
reader's) is fenced as ```python no-run and skipped; keep that rare.
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SKIP = "no-run"


@dataclass(frozen=True)
class Block:
    """One fenced code block: where it is, its info words after the language, its code."""
    path: Path
    line: int  # of the opening fence, 1-based
    flags: tuple[str, ...]
    code: str

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(ROOT) if self.path.is_relative_to(ROOT) else self.path}:{self.line}"


def python_blocks(path: Path, text: str) -> list[Block]:
    """The ```python blocks of a Markdown text, in order. Every fence is followed to its close, so
    that a ```python line shown inside another block (```text, ```markdown) is not taken for code."""
    blocks, lines = [], text.splitlines()
    i = 0
    while i < len(lines):
        if lines[i].lstrip().startswith("```"):
            words = lines[i].strip().removeprefix("```").split()
            end = next((j for j in range(i + 1, len(lines)) if lines[j].strip() == "```"), None)
            if end is None:
                raise AssertionError(f"{path}:{i + 1}: a ``` fence that is never closed")
            if words[:1] == ["python"]:
                blocks.append(Block(path, i + 1, tuple(words[1:]), "\n".join(lines[i + 1:end]) + "\n"))
            i = end
        i += 1
    return blocks


def documents() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def all_blocks() -> list[Block]:
    return [b for doc in documents() for b in python_blocks(doc, doc.read_text(encoding="utf-8"))]


@pytest.fixture(scope="module")
def demo_store(tmp_path_factory) -> Path:
    """The run `gaps demo --paper` makes, alone in a store file (as a reader following the docs has
    it), built once for every block; docs/store.md's examples named a run, demo-001, that no command
    makes (issue 39)."""
    from sim_replay.paper import RUN, paper_run
    from store import Store

    path = tmp_path_factory.mktemp("demo") / "gaps.db"
    with Store(path) as store:
        report = store.append(paper_run(RUN))
        assert report.stored == 20 and not report.rejected, report
    return path


@pytest.mark.parametrize("block", all_blocks(), ids=lambda b: b.where)
def test_doc_example_runs(block: Block, demo_store: Path, tmp_path: Path, monkeypatch) -> None:
    if SKIP in block.flags:
        pytest.skip(f"{block.where} is fenced ```python {SKIP}")
    shutil.copyfile(demo_store, tmp_path / "gaps.db")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("GAPS_DB", str(tmp_path / "gaps.db"))
    exec(compile(block.code, block.where, "exec"), {"__name__": "__doc_example__"})  # noqa: S102 (our own docs)


def test_the_docs_have_examples_to_run():
    found = {b.path.name for b in all_blocks() if SKIP not in b.flags}
    assert {"api.md", "reasoner.md", "store.md"} <= found, found      # api.md: the one way in, taught


def test_python_blocks_are_found_and_others_left_alone():
    text = "\n".join(["intro", "```sh", "gaps demo", "```", "```python", "x = 1", "```",
                      "```text", "```python", "shown, not run", "```",
                      "```python no-run", "open('elsewhere')", "```", "", "  ```python", "  y = 2", "  ```"])
    blocks = python_blocks(Path("doc.md"), text)
    assert [(b.line, b.flags, b.code) for b in blocks] == [
        (5, (), "x = 1\n"), (12, ("no-run",), "open('elsewhere')\n"), (16, (), "  y = 2\n")]


def test_an_unclosed_python_fence_is_an_error():
    with pytest.raises(AssertionError, match="never closed"):
        python_blocks(Path("doc.md"), "```python\nx = 1\n")


def test_the_chain_check_says_so_when_the_run_has_no_events(demo_store, tmp_path, monkeypatch):
    """docs/store.md's check printed a head of 64 zeros, without error, for a run the store lacks."""
    (check,) = [b for b in all_blocks() if "hashlib.sha256(head + canonical)" in b.code]
    shutil.copyfile(demo_store, tmp_path / "gaps.db")
    monkeypatch.chdir(tmp_path)
    code = check.code.replace('run = "paper-junctions"', 'run = "no-such-run"')
    assert code != check.code
    with pytest.raises(AssertionError, match="no events of run 'no-such-run'"):
        exec(compile(code, check.where, "exec"), {"__name__": "__doc_example__"})  # noqa: S102
    before = sorted(p.name for p in tmp_path.iterdir())
    exec(compile(check.code, check.where, "exec"), {"__name__": "__doc_example__"})  # noqa: S102
    assert sorted(p.name for p in tmp_path.iterdir()) == before      # read-only: no -wal, no -shm
