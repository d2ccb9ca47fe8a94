"""Golden runs: recorded runs kept with their approved verdicts, so a rulebook change that flips one
fails the build until someone approves it (`gaps regress --golden FILE --update-golden`).

A golden file is JSON:

    {"format": "gaps-golden/1",
     "recording": "golden-sim.mcap",              # optional: beside the golden file; else --db
     "rulebooks": {"validator": {"name": "validators.le", "sha256": "..."}, ...},   # approved with
     "runs": {"golden-sim": {"incidents": [{"id", "t", "vehicle", "action", "verdict", "rule",
                                            "penalty", "liable"}, ...],
                             "decisions": [{"id", "goal", "answer"}, ...]}}}

The runs are judged with the project's current rulebooks (reasoner/rules/, CURRENT_SET) given for
every stage, not with the rulebooks the recording carries: a golden run exists to show what
today's rules make of it. (`--rules` judges with other files instead.) A recording named in the
file is imported into a temporary store first, so the file alone is the test.
"""
from __future__ import annotations

import json
import tempfile
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Sequence

from store import NoSuchRun, Store, write_text
from store.transfer import TransferError, import_file

from ..bundled import CURRENT_SET, RULES_DIR
from ..engine import Engine, get_engine
from ..facts import FactReader
from ..investigation import Investigation
from ..model import Incident
from .regression import ANSWERS, IN_FORCE, CaseResult, Change, Regression, RunResult
from .books import RegressError, load_given
from .decisions import ask, recorded_decisions, vehicle_choice
from .match import match

FORMAT = "gaps-golden/1"
APPROVE = "approve it with `gaps regress --golden FILE --update-golden` if it is right"


@dataclass(frozen=True)
class Verdict:
    """An incident as the golden file keeps it: enough to see any verdict, penalty or liability change."""

    id: str
    t: int
    vehicle: str
    action: str
    verdict: str
    rule: str | None
    penalty: str
    liable: str

    @classmethod
    def of(cls, inc: Incident) -> Verdict:
        p = inc.penalty
        penalty = "none" if p is None else f"{p.offence}: fine {p.fine_gbp}, points {p.points}"
        return cls(inc.id, inc.t, inc.vehicle, inc.action, inc.verdict, inc.rule, penalty, inc.liable)

    def line(self) -> str:
        return f"{self.verdict} {self.rule or '(no rule)'}, penalty {self.penalty}, liable: {self.liable}"

    def to_json(self) -> dict[str, Any]:
        return dict(self.__dict__)


@dataclass(frozen=True)
class Judged:
    """What one judgement (approved or current) says of a run."""

    incidents: tuple[Verdict, ...]
    decisions: dict[str, tuple[str, str]]          # decision id -> (goal, answer)
    seconds: dict[str, float] = field(default_factory=dict, compare=False)   # judging time, for JUnit only

    def to_json(self) -> dict[str, Any]:
        return {"incidents": [v.to_json() for v in self.incidents],
                "decisions": [{"id": k, "goal": g, "answer": a} for k, (g, a) in self.decisions.items()]}


@dataclass(frozen=True)
class Golden:
    path: Path
    recording: str | None
    rulebooks: dict[str, dict]
    runs: dict[str, Judged]


def read_golden(path: str | Path) -> Golden:
    """The golden file, or a RegressError saying what is wrong with it."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise RegressError(f"no such golden file: {path}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise RegressError(f"golden file {path} is not readable JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT or not isinstance(data.get("runs"), dict):
        raise RegressError(f"golden file {path} is not a {FORMAT} file (it needs \"format\" and \"runs\")")
    try:
        runs = {run: _judged(entry) for run, entry in data["runs"].items()}
    except (KeyError, TypeError, ValueError) as exc:
        raise RegressError(f"golden file {path}: a run's entry is malformed ({exc!r})") from None
    return Golden(path, data.get("recording"), data.get("rulebooks") or {}, runs)


def _judged(entry: dict) -> Judged:
    incidents = tuple(Verdict(**{k: v[k] for k in Verdict.__dataclass_fields__}) for v in entry["incidents"])
    decisions = {d["id"]: (d["goal"], d["answer"]) for d in entry.get("decisions", [])}
    return Judged(incidents, decisions)


@contextmanager
def golden_store(golden: Golden, db: Store | None) -> Iterator[Store]:
    """The store the golden runs are in: the recording the file names, imported into a temporary
    store (deleted after), else the given one."""
    if golden.recording is None:
        if db is None:
            raise RegressError(f"golden file {golden.path} names no recording: pass --db with its runs")
        yield db
        return
    recording = golden.path.parent / golden.recording
    with tempfile.TemporaryDirectory(prefix="gaps-golden-") as tmp:
        store = Store(Path(tmp) / "golden.db")
        try:
            import_file(store, recording)
        except TransferError as exc:
            store.close()
            raise RegressError(f"golden file {golden.path}: its recording: {exc}") from None
        try:
            yield store
        finally:
            store.close()


def judge(store: Store, runs: Sequence[str], rules: Sequence[str] = (), engine: Engine | None = None
          ) -> tuple[dict[str, Judged], dict[str, dict]]:
    """The runs judged with `rules` (default: the project's current rulebooks) for every stage,
    and the rulebook each stage used."""
    engine = engine or get_engine()
    given = load_given(engine, rules or [RULES_DIR / name for name in CURRENT_SET], "--rules")
    inv = Investigation(store, engine, rules=list(given.paths))
    reader = FactReader()
    out, books = {}, {}
    for run in runs:
        started = time.perf_counter()
        rs = inv.ruleset(run)
        decisions = {}
        for d in recorded_decisions(store, run):
            answer = ask(engine, reader, vehicle_choice(rs, d), d).permitted
            decisions[d.id] = (str(d.goal), ANSWERS.get(answer, "not answerable"))
        asked = time.perf_counter()
        verdicts = tuple(Verdict.of(inc) for inc in inv.incidents(run))
        out[run] = Judged(verdicts, decisions, {"decisions": asked - started,
                                                "incidents": time.perf_counter() - asked})
        books = {stage: {"name": Path(c["name"]).name, "sha256": c["sha256"]} for stage, c in rs.describe().items()}
    return out, books


def compare(golden: Golden, judged: dict[str, Judged], books: dict[str, dict]) -> Regression:
    """The judgement against the approved one, as a regression (before: approved, after: now)."""
    why = _why(golden.rulebooks, books)
    results = []
    for run, approved in golden.runs.items():
        now = judged[run]
        incidents = tuple(_incident(run, a, b, why) for a, b in match(approved.incidents, now.incidents))
        decisions = tuple(_decision(run, key, approved.decisions.get(key), now.decisions.get(key), why)
                          for key in dict.fromkeys([*approved.decisions, *now.decisions]))
        results.append(RunResult(run, incidents, decisions, golden.rulebooks, books, seconds=now.seconds))
    return Regression((), IN_FORCE, tuple(results), ())


def write_golden(golden: Golden, judged: dict[str, Judged], books: dict[str, dict]) -> None:
    """Approve the current judgement: the file keeps its recording and gets today's verdicts."""
    data = {"format": FORMAT, **({"recording": golden.recording} if golden.recording else {}),
            "rulebooks": books, "runs": {run: judged[run].to_json() for run in golden.runs}}
    write_text(golden.path, json.dumps(data, indent=1, ensure_ascii=False) + "\n")


def _why(approved: dict[str, dict], now: dict[str, dict]) -> tuple[str, ...]:
    changed = [_changed(stage, approved[stage], now[stage])
               for stage in now if stage in approved and approved[stage].get("sha256") != now[stage]["sha256"]]
    said = ("the rulebooks changed since approval (" + "; ".join(changed) + ")") if changed else \
        "the judgement differs from the approved one with the same rulebooks (the reasoner changed)"
    return (said, "it is not approved: `gaps regress --rules NEW --baseline OLD --run R` names the rules that "
                  "changed; " + APPROVE)


def _changed(stage: str, approved: dict, now: dict) -> str:
    """A stage's rulebook then and now, each hash beside its own file's name."""
    before = f"{approved.get('name')} {str(approved.get('sha256'))[:12]}"
    after = now["sha256"][:12] if approved.get("name") == now["name"] else f"{now['name']} {now['sha256'][:12]}"
    return f"{stage}: {before} -> {after}"


def _incident(run: str, a: Verdict | None, b: Verdict | None, why: tuple[str, ...]) -> CaseResult:
    one = a or b
    if one is None:
        raise ValueError(f"{run}: an incident on neither side")      # match pairs each with one at least
    changes = []
    if a is None or b is None:
        changes.append(Change("new" if a is None else "gone", a.line() if a else None, b.line() if b else None, why))
    elif a.verdict != b.verdict:
        changes.append(Change("verdict", a.verdict, b.verdict, why))
    else:
        for kind, x, y in (("rule", a.rule, b.rule), ("penalty", a.penalty, b.penalty),
                           ("liability", a.liable, b.liable)):
            if x != y:
                changes.append(Change(kind, x, y, why))
    return CaseResult(run, "incident", one.id, one.vehicle, one.action, one.t, a.line() if a else None,
                      b.line() if b else None, tuple(changes))


def _decision(run: str, key: str, a: tuple[str, str] | None, b: tuple[str, str] | None,
              why: tuple[str, ...]) -> CaseResult:
    either = a or b
    if either is None:
        raise ValueError(f"{run}: decision {key} on neither side")    # keys are those of either side
    goal = either[0]
    src = key.rpartition(":")[0]
    before, after = a[1] if a else None, b[1] if b else None
    changes = (Change("decision", before, after, why),) if before != after else ()
    return CaseResult(run, "decision", key, src.rpartition("/")[2], goal, 0, before, after, changes)


def check_golden(path: str | Path, open_db: Callable[[], Store], rules: Sequence[str] = (),
                 runs: Sequence[str] = (), update: bool = False, engine: Engine | None = None) -> Regression:
    """Judge the golden runs and compare them with the approved verdicts; with `update`, approve
    the judgement (writing the file). A golden file that does not exist yet is created by
    `update` for the `runs` of the store `open_db` opens."""
    path = Path(path)
    if not path.exists() and update and runs:
        golden = Golden(path, None, {}, {run: Judged((), {}) for run in runs})
    else:
        golden = read_golden(path)
    db = open_db() if golden.recording is None else None
    try:
        with golden_store(golden, db) as store:
            known = [r.run for r in store.runs()]
            for run in golden.runs:
                if run not in known:
                    raise NoSuchRun(run, known)
            judged, books = judge(store, list(golden.runs), rules, engine)
    finally:
        if db is not None:
            db.close()
    result = compare(golden, judged, books)
    if update:
        write_golden(golden, judged, books)
    return result
