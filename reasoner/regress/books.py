"""The rulebooks a regression compares: the ones given on the command line, and which stage each answers.

`gaps regress --rules NEW [--baseline OLD]` takes files or directories of `.le` files. A stage is
answered by the first given rulebook that defines its sentence (stages.py), so a file that
defines no stage's sentence, or only ones an earlier file already answers, would change nothing:
regressing with it would report "nothing changed" for a reason that has nothing to do with the
rules in it. That is an error here, said with why, never a silent no-op. In a directory the
order is the project's (`CURRENT_SET`: highway_code.le before validators.le, as the in-force set
is read), then by name; a directory's file that no stage uses is listed as unused (a copy of
`reasoner/rules/` holds paper.le, which the Highway Code books shadow) and only a directory none
of whose files is used is an error.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterable

from store import GapsError

from ..bundled import CURRENT_SET
from ..engine import Engine, Rulebook
from ..stages import RuleSet, defines
from ..vocabulary import STAGES


class RegressError(GapsError, ValueError):
    """A regression that cannot be run as asked (a rulebook no stage uses, a missing file, a bad
    golden file); exit 2 with the message."""


@dataclass(frozen=True)
class GivenBooks:
    """Rulebooks given for one side of a regression, in the order stages look for them."""

    books: tuple[Rulebook, ...]
    paths: tuple[str, ...]                   # the file each came from, same order
    stages: dict[str, str]                   # stage -> path of the book that answers it
    unused: tuple[str, ...] = ()             # directory files no stage uses (named files are errors)
    texts: tuple[str, ...] = ()              # their LE, same order: a worker needs no rulebook file

    @property
    def names(self) -> list[str]:
        return list(self.paths)


def rule_files(item: str | Path) -> tuple[list[Path], bool]:
    """The .le files an argument names (a file, or every .le of a directory in stage order) and
    whether it was a directory."""
    path = Path(item)
    if path.is_dir():
        found = sorted(path.glob("*.le"), key=_stage_order)
        if not found:
            raise RegressError(f"{path} holds no .le rulebook")
        return found, True
    if not path.is_file():
        raise RegressError(f"no such rulebook file or directory: {path}")
    return [path], False


def _stage_order(path: Path) -> tuple[int, str]:
    """The project's books in CURRENT_SET's order first (a stage takes the first that defines it)."""
    return (CURRENT_SET.index(path.name) if path.name in CURRENT_SET else len(CURRENT_SET), path.name)


@dataclass(frozen=True)
class BookText:
    """A given rulebook's text and where it came from: what a cluster's worker loads, so that it
    needs the project, not the files the rulebooks were read from."""

    path: str
    text: str
    from_dir: bool


def read_given(items: Iterable[str | Path]) -> tuple[BookText, ...]:
    """The texts of every rulebook the arguments name, in the order stages look for them."""
    return tuple(BookText(str(path), path.read_text(encoding="utf-8"), is_dir)
                 for item in items for files, is_dir in [rule_files(item)] for path in files)


def load_given(engine: Engine, items: Iterable[str | Path], what: str = "--rules") -> GivenBooks:
    """Load every rulebook the arguments name and check each is used by some stage: an LEError
    (file:line:column) for one that does not compile, a RegressError for one no stage uses."""
    return load_texts(engine, read_given(items), what)


def load_texts(engine: Engine, texts: Iterable[BookText], what: str = "--rules") -> GivenBooks:
    """load_given on texts already read (a worker's half of it)."""
    texts = tuple(texts)
    if not texts:
        raise RegressError(f"{what} names no rulebook")
    books = [engine.load(t.text, t.path) for t in texts]
    paths = [t.path for t in texts]
    stages = RuleSet(engine, books, [], []).stages
    used = {choice.rulebook.sha256: stage for stage, choice in stages.items()}
    answered = {stage: paths[books.index(choice.rulebook)] for stage, choice in stages.items()}
    unused = [i for i, rb in enumerate(books) if rb.sha256 not in used]
    named = [i for i in unused if not texts[i].from_dir]
    if named:
        raise RegressError(f"{what} {paths[named[0]]} is used by no stage: {_why_unused(books[named[0]], answered)}")
    if unused and len(unused) == len(books):
        raise RegressError(f"{what}: none of the rulebooks is used by a stage: "
                           + "; ".join(f"{paths[i]}: {_why_unused(books[i], answered)}" for i in unused))
    return GivenBooks(tuple(books), tuple(paths), answered, tuple(paths[i] for i in unused),
                      tuple(t.text for t in texts))


def _why_unused(rb: Rulebook, answered: dict[str, str]) -> str:
    """Why a rulebook answers no stage: it defines none of their sentences, or an earlier one does."""
    mine = [stage for stage, sentence in STAGES.items() if defines(rb, sentence.functor)]
    if not mine:
        asked = ", ".join(f"{stage} ({STAGES[stage].template})" for stage in STAGES)
        return f"it defines none of the stages' sentences ({asked}), so it would change no verdict"
    return "the stages it defines are answered by rulebooks given before it: " + \
        ", ".join(f"{stage} by {answered[stage]}" for stage in mine)
