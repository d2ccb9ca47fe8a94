"""One run, one producer, before a replay publishes: ask the ingests what they hold of the run.

A replay publishes to a `gaps serve` whose store it cannot see. Before it puts the first event of
run X, it asks the ingests' history queryable (ingest/history_queryable.py, the query `gaps fetch`
makes) for the first page of what they hold of `gaps/X/**` and compares each event with the one the
recording holds under the same identity (run, src, seq), as `gaps import` compares a file's first
events with the store's (Store.first_conflict). An event the ingests hold with other content means
that run X there is another producer's: the replay is refused before anything of it is published
(RunHeldElsewhere, exit 2). A simulation publishing to a serve (`gaps sim --connect/--listen`)
compares its first batch (the run's start and its sources' first events) the same way. The same
events again and a run the ingests hold only part of (a
resumed run) agree and go out. Nothing answering (a plain subscriber, no serve) is no objection.
The ingest refuses such a run itself too (ingest/run_claims.py): this is the producer saying so
first, clearly, and publishing nothing.
"""
from __future__ import annotations

import zenoh

from store import Candidate, EventError, GapsError, Store, canonical_json, decode_event
from store.wire import SYNC_KEY, key_for, matched_within

PAGE = 1000             # events of the run asked for: its chain's first (what a replay begins with)
MATCH_S = 1.0           # how long an ingest's queryables may take to be known here after its subscriber
ANSWER_S = 10.0         # how long the ingests may take to answer


class RunHeldElsewhere(GapsError):
    """The ingests hold the run with other events than the recording's (exit 2: choose another store)."""


def refuse_if_held(session: zenoh.Session, store: Store, run: str) -> None:
    """RunHeldElsewhere if an ingest reachable from `session` holds an event of `run` that the
    recording `store` holds under the same identity with other content."""
    conflict = store.first_conflict(held_events(session, run))
    if conflict is not None:
        _refuse(run, conflict, "this recording's", "replay it to a gaps serve of another store")


def refuse_if_held_otherwise(session: zenoh.Session, events: list[dict]) -> None:
    """RunHeldElsewhere if an ingest holds an event under the identity of one of `events` (a
    simulation's first batch) with other content; a signature is left out of the comparison
    (the same simulation signed again is the same simulation)."""
    if not events:
        return
    run = events[0]["run"]
    own = {(e["run"], e["src"], e["seq"]): _unsigned(e) for e in events}
    for held in held_events(session, run):
        ev = held.event
        assert ev is not None       # _candidate keeps only events it read
        mine = own.get((ev["run"], ev["src"], ev["seq"]))
        if mine is not None and mine != _unsigned(ev):
            _refuse(run, (run, ev["src"], ev["seq"]), "this simulation's", "give another --run")


def held_events(session: zenoh.Session, run: str) -> list[Candidate]:
    """The first page of what the ingests reachable from `session` hold of `run` (none when no
    gaps serve answers there)."""
    if not matched_within(session.declare_querier(SYNC_KEY), MATCH_S, 0.02):
        return []      # no gaps serve answers here: nothing to compare with
    replies = session.get(f"gaps/{run}/**?_limit={PAGE}", target=zenoh.QueryTarget.ALL,
                          consolidation=zenoh.ConsolidationMode.NONE, timeout=ANSWER_S,
                          allowed_destination=zenoh.Locality.REMOTE)
    return [candidate for reply in replies if reply.ok is not None
            and (candidate := _candidate(reply.ok, run)) is not None]


def _refuse(run: str, conflict: tuple[str, str, int], whose: str, instead: str) -> None:
    _, src, seq = conflict
    raise RunHeldElsewhere(
        f"run {run} is held by the ingest with other events than {whose} (its {src} seq {seq} differs): a run "
        f"holds one producer's events, so nothing of run {run} was published; {instead}")


def _unsigned(event: dict) -> bytes:
    return canonical_json({k: v for k, v in event.items() if k != "sig"})


def _candidate(sample: zenoh.Sample, run: str) -> Candidate | None:
    """The answer as a store candidate, if it is an event of the run on its own key."""
    key, payload = str(sample.key_expr), sample.payload.to_bytes()
    try:
        event, canonical = decode_event(payload)
    except EventError:
        return None
    if event["run"] != run or key_for(event) != key:
        return None
    return Candidate(key, payload, event, canonical)
