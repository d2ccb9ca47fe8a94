"""Which rulebook answers which question of an investigation.

The paper's Figure 1 has stages, each a question to a rulebook (reasoner/rules/README.md):

    monitor    Monitor Scenario  -> V potentially violates A          (monitors.le)
    validator  Validator Scenario -> V punishably / mitigately violates A (validators.le)
    vehicle    the vehicle's own perception -> V can A              (highway_code.le)
    penalties  punishable violation -> offence, law, fine, points   (penalties.le)
    liability  ads.event history -> who answers                    (liability.le)

A stage is answered by a rulebook that *defines* its sentence (has a rule with that head), so a
run that recorded only the paper's rulebook (which defines the first three) is judged by it where
it can be, and by the project's current rulebooks for the rest. The order of preference is:
rulebooks given by the investigator (`--rules`), then the ones the run recorded (in `run.start`,
or in the store by the sha256 an event names), then the project's current ones. Each stage says
which it used, so no output hides that it was judged by other rules than the run's own.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

from store import Store

from .bundled import CURRENT_SET, bundled
from .engine import Engine, Rulebook, sha256_text
from .le.errors import LEError
from .vocabulary import STAGES


@dataclass(frozen=True)
class Choice:
    """The rulebook a stage is answered by, and where it came from: "given", "recorded", "current"."""

    rulebook: Rulebook
    source: str

    def describe(self) -> dict:
        return {"name": self.rulebook.name, "sha256": self.rulebook.sha256, "source": self.source}


def defines(rb: Rulebook, functor: str) -> bool:
    return any(rule.head.functor == functor for rule in rb.document.rules)


class RuleSet:
    """The rulebooks of one run, loaded once, and the choice for each stage."""

    def __init__(self, engine: Engine, given: list[Rulebook], recorded: list[Rulebook],
                 current: list[Rulebook]) -> None:
        self.engine = engine
        self.by_sha: dict[str, Rulebook] = {rb.sha256: rb for rb in (*current, *recorded, *given)}
        self.stages: dict[str, Choice] = {}
        for stage, question in STAGES.items():
            for source, books in (("given", given), ("recorded", recorded), ("current", current)):
                found = next((rb for rb in books if defines(rb, question.functor)), None)
                if found is not None:
                    self.stages[stage] = Choice(found, source)
                    break

    def __getitem__(self, stage: str) -> Choice | None:
        return self.stages.get(stage)

    def vehicle_rulebook(self, sha: str | None) -> Choice | None:
        """The rulebook a vehicle says it decided with; the vehicle stage's choice if unknown."""
        if sha and sha in self.by_sha and defines(self.by_sha[sha], STAGES["vehicle"].functor):
            return Choice(self.by_sha[sha], "recorded")
        return self.stages.get("vehicle")

    def describe(self) -> dict:
        return {stage: choice.describe() for stage, choice in self.stages.items()}


def recorded_rulebooks(engine: Engine, store: Store, run: str, shas: Iterable[str] = (),
                       problems: list[str] | None = None) -> list[Rulebook]:
    """The run's own rulebooks: the LE texts in its run.start, then any named by sha256 in its
    events that the store's rulebook table holds. A recorded text whose sha256 does not match the
    one recorded beside it is not used, and said so in `problems`."""
    books: list[Rulebook] = []
    seen: set[str] = set()
    problems = [] if problems is None else problems
    for start in store.events(run, kinds=["run.start"]):
        for entry in start["body"].get("rulebooks") or []:
            text = entry.get("text") if isinstance(entry, dict) else None
            if not isinstance(text, str):
                continue
            sha = sha256_text(text)
            if entry.get("sha256") not in (None, sha):
                problems.append(f"run.start (seq {start['seq']}) records rulebook {entry.get('name')!r} "
                                f"with sha256 {entry.get('sha256')} but its text hashes to {sha}: not used")
                continue
            if sha in seen:
                continue
            seen.add(sha)
            _load(engine, text, str(entry.get("name") or "<recorded>"), books, problems)
    for sha in shas:
        if sha and sha not in seen and (stored := store.get_rulebook(sha)):
            seen.add(sha)
            _load(engine, stored["text"], stored["name"], books, problems)
    return books


def _load(engine: Engine, text: str, name: str, books: list[Rulebook], problems: list[str]) -> None:
    """A recorded rulebook that does not compile is reported, not fatal: its stages fall back."""
    try:
        books.append(engine.load(text, name))
    except LEError as exc:
        problems.append(f"recorded rulebook {name!r} does not compile ({exc}); not used")


def current_rulebooks(engine: Engine) -> list[Rulebook]:
    return [engine.load(bundled(name), name) for name in CURRENT_SET]


def given_rulebooks(engine: Engine, rules: Iterable[str]) -> list[Rulebook]:
    """Rulebooks an investigator passes in: paths to .le files, or LE text."""
    from pathlib import Path

    books = []
    for item in rules:
        path = Path(item) if "\n" not in item and len(item) < 4096 else None
        if path is not None and path.is_file():
            books.append(engine.load(path.read_text(encoding="utf-8"), str(path)))
        else:
            books.append(engine.load(item, "<given>"))
    return books
