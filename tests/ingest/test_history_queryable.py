"""The history queryable answers `gaps/<run>/<src>/<kind>?_time=[t1..t2]` from the store: real Zenoh
sessions on loopback (scouting off), a real store written before the ingest opens it."""
from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh

from ingest import IngestService
from ingest.history_queryable import HistoryQueryable
from ingest.time_range import rfc3339
from store import Store, canonical_json
from store.wire import session_config
from tests.helpers.ingest_testkit import T0, free_endpoint, make_event

STEP = 100_000_000  # make_event: t = T0 + seq * 0.1 s


def recorded() -> list[dict]:
    """Two runs; three sources of run-a (two vehicles, a signal), one vehicle of run-b."""
    events = []
    for seq in range(10):
        events.append(make_event("vehicle/1", seq, "entity.state", run="run-a"))
        events.append(make_event("vehicle/2", seq, "vehicle.perception" if seq % 2 else "entity.state",
                                 run="run-a"))
        events.append(make_event("signal/j1", seq, "signal.state", run="run-a"))
        events.append(make_event("vehicle/9", seq, "entity.state", run="run-b"))
    return events


@pytest.fixture
def served(tmp_path: Path) -> Iterator[tuple[zenoh.Session, Path]]:
    """An ingest on a store holding `recorded()`, and a client session connected to it."""
    db = tmp_path / "source.db"
    with Store(db) as store:
        store.append(recorded())
    endpoint = free_endpoint()
    with IngestService(db, listen=[endpoint]):
        session = zenoh.open(session_config(connect=[endpoint], mode="client"))
        try:
            yield session, db
        finally:
            session.close()


def ask(session: zenoh.Session, selector: str) -> tuple[list[zenoh.Sample], list[dict]]:
    """Every reply to one query: the samples, and the error replies' JSON."""
    samples, errors = [], []
    for reply in session.get(selector, target=zenoh.QueryTarget.ALL, consolidation=zenoh.ConsolidationMode.NONE,
                             timeout=10):
        if reply.ok is not None:
            samples.append(reply.ok)
        else:
            errors.append(json.loads(reply.err.payload.to_bytes()))
    return samples, errors


def ids(samples: list[zenoh.Sample]) -> list[tuple[str, str, int]]:
    events = [json.loads(s.payload.to_bytes()) for s in samples]
    return [(e["run"], e["src"], e["seq"]) for e in events]


def expected(pick) -> list[tuple[str, str, int]]:
    """The recorded events `pick` selects, in the order the store chained them (append order)."""
    return [(e["run"], e["src"], e["seq"]) for e in recorded() if pick(e)]


def test_a_run_comes_back_as_stored_in_chain_order(served):
    session, db = served
    samples, errors = ask(session, "gaps/run-a/**")
    assert errors == []
    assert ids(samples) == expected(lambda e: e["run"] == "run-a")
    with Store.open_read_only(db) as store:
        stored = list(store.history("run-a"))
    for sample, row in zip(samples, stored, strict=True):
        assert sample.payload.to_bytes() == row.event.encode() == canonical_json(json.loads(row.event))
        assert str(sample.key_expr) == f"gaps/run-a/{row.src}/{row.kind}"
        assert str(sample.encoding) == "application/json"
        assert json.loads(sample.attachment.to_bytes()) == {"chain_pos": row.chain_pos, "hash": row.hash}


def test_the_key_expression_selects_sources_and_kinds(served):
    session, _ = served
    vehicles, _ = ask(session, "gaps/run-a/vehicle/*/**")
    assert ids(vehicles) == expected(lambda e: e["run"] == "run-a" and e["src"].startswith("vehicle/"))
    one, _ = ask(session, "gaps/run-a/vehicle/2/vehicle.perception")
    assert ids(one) == expected(lambda e: e["src"] == "vehicle/2" and e["kind"] == "vehicle.perception")
    states, _ = ask(session, "gaps/**/entity.state")   # every run, one kind
    assert sorted(ids(states)) == sorted(expected(lambda e: e["kind"] == "entity.state"))
    assert ask(session, "gaps/run-z/**") == ([], [])


def test_time_ranges_in_zenohs_syntax(served):
    session, _ = served
    t2, t5 = rfc3339(T0 + 2 * STEP), rfc3339(T0 + 5 * STEP)

    def seqs(time_range: str) -> set[int]:
        samples, errors = ask(session, f"gaps/run-b/**?_time={time_range}")
        assert errors == []
        return {seq for _, _, seq in ids(samples)}

    assert seqs(f"[{t2}..{t5}]") == {2, 3, 4, 5}
    assert seqs(f"]{t2}..{t5}[") == {3, 4}
    assert seqs(f"[..{t2}]") == {0, 1, 2}
    assert seqs(f"[{t5}..]") == {5, 6, 7, 8, 9}
    assert seqs(f"[{t2}%3B0.3s]") == {2, 3, 4, 5}   # [t;duration], its ; escaped
    assert seqs("[..]") == set(range(10))
    assert seqs("[now(-1h)..]") == set()          # the events are of 2024
    assert seqs("[..now()]") == set(range(10))


@pytest.mark.parametrize("selector, says", [
    ("gaps/**?_time=[2024-11-21T08:00:00Z..", "_time='[2024-11-21T08:00:00Z..'"),
    ("gaps/**?_time=[yesterday..]", "'yesterday' is not a time"),
    ("gaps/**?_time=[now(-1q)..]", "'1q' is not a duration"),
    ("gaps/**?_limit=0", "_limit='0'"),
    ("gaps/**?_after=run-a", "_after='run-a'"),
    ("gaps/**?time=[..]", "unknown parameter 'time'"),
])
def test_a_malformed_selector_gets_an_error_reply_not_a_crash(served, selector, says):
    session, _ = served
    samples, errors = ask(session, selector)
    assert samples == []
    assert [e["error"] for e in errors] == ["selector"] and says in errors[0]["message"]
    assert len(ask(session, "gaps/run-b/**")[0]) == 10   # and it still answers


def test_a_limit_cuts_the_answer_and_says_where_to_resume(served):
    session, _ = served
    everything = expected(lambda e: e["run"] == "run-a") + expected(lambda e: e["run"] == "run-b")
    pages, after = [], None
    while True:
        samples, errors = ask(session, "gaps/**?_limit=13" + (f";_after={after}" if after else ""))
        pages.append(ids(samples))
        if not errors:
            break
        assert errors[0]["error"] == "limit" and errors[0]["sent"] == 13 == len(samples)
        after = errors[0]["next"]
    assert [len(p) for p in pages] == [13, 13, 13, 1]
    assert [i for page in pages for i in page] == everything   # each once, runs by name, chain order


def test_an_ingest_answers_for_its_own_slice_only(tmp_path):
    db = tmp_path / "both.db"
    with Store(db) as store:
        store.append(recorded())
    endpoint = free_endpoint()
    with IngestService(db, listen=[endpoint], key_expr="gaps/run-b/**"):
        session = zenoh.open(session_config(connect=[endpoint], mode="client"))
        try:
            samples, errors = ask(session, "gaps/**")
        finally:
            session.close()
    assert errors == [] and ids(samples) == expected(lambda e: e["run"] == "run-b")


def test_a_full_queue_is_refused_as_busy_at_once(tmp_path):
    """Zenoh's thread never waits for a worker: with none free and no room, the query is refused."""
    db = tmp_path / "s.db"
    with Store(db) as store:
        store.append(recorded())
    endpoint = free_endpoint()
    owner = zenoh.open(session_config(listen=[endpoint]))
    history = HistoryQueryable(owner, db, "gaps/**", workers=0, backlog=1)
    session = zenoh.open(session_config(connect=[endpoint], mode="client"))
    try:
        first = session.get("gaps/**", timeout=2)        # waits in the queue: nobody takes it
        second = ask(session, "gaps/**")
        assert second[0] == [] and [e["error"] for e in second[1]] == ["busy"]
        history.close()                                   # the waiting one is told the ingest stops
        assert [json.loads(r.err.payload.to_bytes())["error"] for r in first] == ["stopping"]
    finally:
        session.close()
        owner.close()
