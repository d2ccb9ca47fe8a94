"""The vehicle's status at the act's moment (DESIGN "Weighing": the latest record before it).

A case is judged on the state at its time; where the act's own moment differs and the record
changed the vehicle's spawn, state or ADS status in between (an ADS overridden, a call stood
down just after the act), those are read at the act. Its perception and decision stay those at
the case's time (DESIGN "Reasoning": the Vehicle Scenario at t).
"""
from __future__ import annotations

from dataclasses import replace

from .case import Case
from .court import Court


def at_act(court: Court, case: Case, at: int | None) -> Case:
    """The case with the vehicle's spawn, latest entity.state and ADS status as recorded at `at`."""
    src = f"vehicle/{case.vehicle}"
    record = case.state.entities.get(src)
    if at is None or at == case.t or record is None:
        return case
    if at > case.t and not changed_before(court, case, record, at):
        return case
    if at < case.t and not changed_after(record, at):
        return case
    then = court.state(case.run, at, case.vehicle, case.monitor).entities.get(src)
    if then is None:
        return case
    merged = {**record, **{kind: then.get(kind) for kind in ("spawn", "state", "ads", "despawned")}}
    return replace(case, state=replace(case.state, entities={**case.state.entities, src: merged}))


def changed_before(court: Court, case: Case, record: dict, at: int) -> bool:
    """Whether the vehicle's status may have changed between the case's time and its act, later
    (a camera that flagged the car on its way to the line): an ads.event or a spawn of it in
    between (its DSSAD record: a driver override just before it crossed), or, for a vehicle on
    or once on an emergency call, any state in between."""
    src, store = f"vehicle/{case.vehicle}", court.store
    if store.source_events(case.run, src, kinds=["ads.event", "entity.spawn"], t_from=case.t + 1, t_to=at):
        return True
    spawn = ((record.get("spawn") or {}).get("body") or {}).get("emergency")
    state = (record.get("state") or {}).get("body") or {}
    return (spawn is True or state.get("emergency") is True) and bool(
        store.source_events(case.run, src, kinds=["entity.state"], t_from=case.t + 1, t_to=at))


def changed_after(record: dict, at: int) -> bool:
    """Whether the vehicle's status may have changed between the act and the record's time: an
    ads.event after it, or, for a vehicle that is or was on an emergency call, a state after it."""
    ads = (record.get("ads") or {}).get("last")
    if ads and ads.get("t", 0) > at:
        return True
    spawn = ((record.get("spawn") or {}).get("body") or {}).get("emergency")
    state = record.get("state") or {}
    return (spawn is True or (state.get("body") or {}).get("emergency") is True) and state.get("t", 0) > at
