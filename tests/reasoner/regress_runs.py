"""A small recorded run and modified copies of the bundled rulebooks, for the regression tests.

The run (tests/helpers/verdict_runs.RunBuilder, the five current rulebooks recorded in its
run.start) holds four crossings of junction j1:

    5   amber, too close to stop, recorded by m1       -> mitigated (HC 175); its decision: permitted
    7   red, recorded by m1                             -> punishable (HC 176), £100 + 3 points
    9   red, not recorded (re-derived from m1's view)   -> punishable (HC 176)
    11  green, not recorded                             -> no incident
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from reasoner.bundled import bundled
from store import Store
from tests.helpers.verdict_runs import RUN, RunBuilder, car

# Each rule to cut is named by the comment line just above it; the cut runs to the next blank line.
AMBER_TOO_CLOSE = '% "or are so close to it that to stop might cause a collision"'
RED_CROSSED = "% proceeding beyond the stop line while the red signal (alone, or with amber) shows"
RED_SNAPSHOT = "% a snapshot: over the line with red showing, and no record of the light it crossed on"
GREEN_RULE = ("\n% a test's rule, unlabelled: entering on green is a potential violation\n"
              "a vehicle potentially violates enter the junction if\n"
              "    the vehicle has green light\n"
              "    and the vehicle has crossed the stop line.\n")


def build_store(path: Path, runs: tuple[str, ...] = (RUN,)) -> Path:
    """A store holding the run above under each of the names `runs`."""
    with Store(path) as store:
        for name in runs:
            store.append(_events(name))
    return path


def _events(name: str) -> list[dict]:
    run = RunBuilder(run=name)
    for v in ("5", "7", "9", "11"):
        run.spawn(v)
    run.signal("amber", 9.0)
    run.crossing("5", at=10, perceived=car("5") + ["5 has amber light", "5 is too close to the stop line to stop safely"],
                 observed=["5 has amber light", "5 has crossed the stop line"])
    run.signal("red", 19.0)
    run.crossing("7", at=20, perceived=car("7") + ["7 has red light"], observed=["7 has red light",
                                                                                 "7 has crossed the stop line"])
    run.signal("green", 29.0)
    run.crossing("11", at=30, perceived=car("11") + ["11 has green light"], record=False,
                 observed=["11 has green light", "11 has crossed the stop line"])
    run.signal("red", 39.0)
    run.crossing("9", at=40, perceived=car("9") + ["9 has red light"], record=False,
                 observed=["9 has red light", "9 has crossed the stop line"])
    return run.finish()


def edited(tmp: Path, name: str, cut: tuple[str, ...] = (), add: str = "", old: str = "", new: str = "") -> Path:
    """A copy of a bundled rulebook (as `tmp/name`) with the rules under the `cut` comments
    removed, `old` replaced by `new` and the rules `add` put at the end of its knowledge base."""
    text = bundled(name)
    for marker in cut:
        start = text.index(marker)
        end = text.index("\n\n", start)
        text = text[:start] + text[end + 2:]
    if old:
        assert old in text, old
        text = text.replace(old, new)
    if add:
        at = text.index("\nscenario ")
        text = text[:at] + add + text[at:]
    path = tmp / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


__all__ = ["RUN", "build_store", "edited"]


def regressed(db: Path, rules: Path) -> dict:
    """`regress` of the run under `rules` against the rulebooks in force, as its JSON."""
    from reasoner.regress import regress
    with Store.open_read_only(db) as store:
        return regress(store, [str(rules)], runs=[RUN]).to_json()


def plain(db: Path, rules: Path) -> dict:
    """The same regression with nothing kept: every case measured and judged, every decision
    asked; what every kept road must equal, to the byte."""
    from reasoner.regress import regression as regress_module
    engine = regress_module.get_engine()
    new = regress_module.load_given(engine, [str(rules)])
    with Store.open_read_only(db) as store:
        part = regress_module.Regressor(store, engine, new, None, kept=False).part(RUN)
        return regress_module.assemble(new, None, [part]).to_json()


def summarised(store: Store, rules: Path) -> tuple[list, list, Any]:
    """The run's incidents judged whole; as a regression's new side judges them (each by its
    summary, every one checked to be an IncidentSummary); and the investigation that judged them so
    (Speedups.NEW_SIDE)."""
    from reasoner.investigation import IncidentSummary, Investigation, Speedups
    full = Investigation(store, rules=[str(rules)]).incidents(RUN)
    lean = Investigation(store, rules=[str(rules)], speedups=Speedups.NEW_SIDE)
    found = lean.judgements(RUN)
    assert found and all(isinstance(i, IncidentSummary) for i in found)
    return full, found, lean


def shaping(monkeypatch) -> list:
    """Calls of Shapes._shape (parsing and shaping a decision's sentences), counted."""
    from reasoner.regress import decisions as regress_decisions
    calls: list = []
    shape = regress_decisions.Shapes._shape
    monkeypatch.setattr(regress_decisions.Shapes, "_shape", lambda self, *a: calls.append(a) or shape(self, *a))
    return calls


@pytest.fixture
def db(tmp_path):
    """The run's store (a fixture: import it into a test module)."""
    return build_store(tmp_path / "gaps.db")


@pytest.fixture
def new_rules(tmp_path):
    """validators.le without its amber exception: it answers the vehicle stage too, so verdicts
    and decisions change (a fixture: import it into a test module)."""
    return edited(tmp_path / "new", "validators.le", cut=(AMBER_TOO_CLOSE,))
