"""A run's cases to judge, in time order: the recorded potential violations, the episodes the
monitor rulebook re-derives from the observations, the acts the sweep of the measurements finds.

A case to judge is a `Todo`, (t, monitor, recorded potential violation or None, episode or None);
`case_of` reads the state it is judged on.
"""
from __future__ import annotations

from typing import Any, Iterable

from store import CollectorPaused, Store

from .. import acts, stretches
from ..engine import Engine
from ..episodes import Episode, Rederiver, episodes, match
from ..facts import FactReader
from ..history import RunContext
from ..stages import RuleSet
from ..sweep import Candidate, Sweep
from .case import SECOND, Case, anchor_key
from .court import Court

Todo = tuple[int, str, dict | None, Episode | None]
SWEPT_NEAR_S = 15.0                   # a swept act this close to a judged one of the vehicle is that one


def find(store: Store, engine: Engine, reader: FactReader, context: RunContext, run: str, rs: RuleSet,
         recorded: list[dict]) -> list[Todo]:
    """The run's cases, found afresh (reasoner/speedups/kept_cases.py keeps them)."""
    monitor = rs["monitor"]
    eps: list[Episode] = []
    swept: list[Candidate] = []
    if monitor is not None:
        rederiver = Rederiver(engine, monitor.rulebook, reader)
        sweeper = Sweep(context.map)
        own = Sweep(context.map)     # the road users' own record, swept apart (its own time order)
        with CollectorPaused():    # hundreds of thousands of parsed observations, no cycles
            eps = list(episodes(_fed(store.events(run, kinds=["monitor.observation"]), sweeper), rederiver))
            for state in store.events(run, kinds=["entity.state"]):
                if _well_formed(state):         # a damaged row's event is no measurement
                    own.add(state)
        swept = sorted(sweeper.candidates() + own.candidates(), key=lambda c: (c.t, c.event["src"], c.event["seq"]))
    todo: list[Todo] = [(pv["t"], pv["src"], pv, episode) for pv, episode in match(eps, recorded)]
    todo += [(ep.first["t"], ep.monitor, None, ep) for ep in eps if not ep.recorded]
    todo += unrecorded(context, swept, todo)
    todo.sort(key=lambda item: (item[0], anchor_key(item[2], item[3])))
    return todo


def unrecorded(context: RunContext, swept: list[Candidate], todo: list[Todo]) -> list[Todo]:
    """The swept candidates no recorded or re-derived potential violation of the same act
    already covers, as one-observation episodes. A speeding candidate is the start of a
    stretch over the limit, and is passed over only within the stretch's own gap tolerance
    of another: a second stretch soon after a first is another act (the cases of one act
    are one incident after judging, reasoner/oneact.py)."""
    near = int(SWEPT_NEAR_S * SECOND)
    near_speeding = int(stretches.STRETCH_GAP_S * SECOND)
    taken: dict[tuple[str, str], list[int]] = {}
    for t, _, pv, ep in todo:
        taken.setdefault(_acted(pv, ep), []).append(t)
    out: list[Todo] = []
    for c in swept:
        times = taken.setdefault((c.user, c.action), [])
        if any(abs(c.t - t) <= (near_speeding if c.action == acts.SPEEDING else near) for t in times):
            continue
        times.append(c.t)
        junction = context.map.junction(c.junction)
        src = c.event["src"] if c.event.get("kind") == "monitor.observation" or not junction or not junction.monitors \
            else junction.monitors[0]
        out.append((c.t, src, None, Episode(src, c.user, c.action, [c.event])))
    return out


def case_of(court: Court, run: str, rs: RuleSet, todo: Todo) -> Case:
    """The case to judge, with the state of the run at its time."""
    t, src, pv, ep = todo
    vehicle, action = _acted(pv, ep)
    return Case(run, rs, court.state(run, t, vehicle, src), t, src, pv, ep, vehicle, action)


def _acted(pv: dict | None, ep: Episode | None) -> tuple[str, str]:
    """The vehicle and the action of a case: its recorded potential violation's, else its episode's."""
    if pv:
        body = pv["body"]
        return str(body.get("vehicle")), str(body.get("action"))
    assert ep is not None, "a case is a recorded potential violation or an episode"
    return ep.vehicle, ep.action


def _well_formed(event: Any) -> bool:
    return type(event) is dict and type(event.get("body")) is dict and type(event.get("t")) is int \
        and type(event.get("src")) is str and type(event.get("seq")) is int


def _fed(events: Iterable[dict], sweeper: Sweep) -> Iterable[dict]:
    """The events, each shown to the sweeper on its way through."""
    for event in events:
        sweeper.add(event)
        yield event
