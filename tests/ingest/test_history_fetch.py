"""`gaps fetch`: a store on another machine rebuilt from an ingest's history answers, its chains
checked against the sender's (loopback Zenoh, scouting off, real stores)."""
from __future__ import annotations

import hashlib
import json
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh

from ingest import AnswerError, IngestService
from ingest.history_fetch import FetchOptions, NothingAnswers, fetch
from store import Rejection, Store
from store.wire import SYNC_KEY, BrokenLink, ReceivedChain, session_config
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import T0, free_endpoint, make_event


def recorded() -> list[dict]:
    """Two runs, appended out of time order in places, so chain order is not time order."""
    events = [make_event(f"vehicle/{v}", seq, "entity.state", run=run)
              for seq in range(30) for run in ("run-a", "run-b") for v in (1, 2)]
    late = [e for e in events if e["src"] == "vehicle/2" and e["seq"] % 7 == 3]
    return [e for e in events if e not in late] + late


@pytest.fixture
def source(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    """An ingest serving a store that holds `recorded()`: (its endpoint, the store)."""
    db = tmp_path / "source.db"
    with Store(db) as store:
        store.append(recorded())
    endpoint = free_endpoint()
    with IngestService(db, listen=[endpoint]):
        yield endpoint, db


def heads(db: Path) -> dict[str, tuple[int, str]]:
    with Store.open_read_only(db) as store:
        return {run: store.chain_head(run) for run in store.run_names()}


def file_sha(db: Path) -> str:
    return hashlib.sha256(db.read_bytes()).hexdigest()


def test_a_fetched_store_is_the_senders_chain_and_verifies(source, tmp_path):
    endpoint, db = source
    copy = tmp_path / "copy.db"
    report = fetch(copy, FetchOptions("gaps/**", connect=(endpoint,), page=17))  # 120 events: 8 pages
    assert (report.received, report.stored, report.duplicates, report.rejected) == (120, 120, 0, 0)
    assert report.pages == 8 and report.complete and report.exit_code == 0
    assert heads(copy) == heads(db)
    assert [(c.run, c.match, c.links_checked) for c in report.chains] == [("run-a", True, 60),
                                                                                   ("run-b", True, 60)]
    assert gaps("verify", db=copy).exit_code == 0
    again = fetch(copy, FetchOptions("gaps/run-a/**", connect=(endpoint,)))
    assert (again.stored, again.duplicates, again.exit_code) == (0, 60, 0)   # fetching twice changes nothing
    assert heads(copy) == heads(db)


def test_a_window_is_checked_link_by_link_and_said_not_comparable(source, tmp_path):
    endpoint, _ = source
    copy = tmp_path / "copy.db"
    report = fetch(copy, FetchOptions("gaps/run-b/vehicle/1/**", connect=(endpoint,),
                                      t_from=T0 + 10 * 100_000_000, t_to=T0 + 19 * 100_000_000))
    assert report.received == report.stored == 10 and report.exit_code == 0
    [chain] = report.chains
    assert chain.match is None and chain.first_mismatch is None
    with Store.open_read_only(copy) as store:
        assert [e["seq"] for e in store.events("run-b")] == list(range(10, 20))


def test_a_window_from_the_start_matches_a_prefix_of_the_chain(source, tmp_path):
    endpoint, db = source
    first = fetch(tmp_path / "first.db", FetchOptions("gaps/run-a/**", connect=(endpoint,),
                                                       t_to=T0 + 2 * 100_000_000))
    [chain] = first.chains
    with Store.open_read_only(db) as store:
        stated = {row.chain_pos: row.hash for row in store.history("run-a")}
    assert (chain.received, chain.last_chain_pos, chain.match) == (6, 5, True)
    assert chain.store_head == stated[5]
    # up to 0.4 s the window has a hole: vehicle/2's seq 3 was chained late, after the rest
    holed = fetch(tmp_path / "holed.db", FetchOptions("gaps/run-a/**", connect=(endpoint,),
                                                      t_to=T0 + 4 * 100_000_000))
    assert [(c.received, c.match, c.first_mismatch) for c in holed.chains] == [(10, None, None)]


def test_an_event_altered_on_the_way_breaks_its_link(tmp_path):
    """A sender whose bytes do not hash to the chain it states: the copy says where, exit 1."""
    events = [make_event("vehicle/1", seq, "entity.state", run="run-x") for seq in range(3)]
    with Store(tmp_path / "honest.db") as store:
        store.append(events)
        rows = list(store.history("run-x"))
    endpoint = free_endpoint()
    liar = zenoh.open(session_config(listen=[endpoint]))

    def answer(query: zenoh.Query) -> None:
        with query:
            for row in rows:
                text = row.event.replace('"x":1.5', '"x":9.5') if row.chain_pos == 1 else row.event
                query.reply(f"gaps/run-x/{row.src}/{row.kind}", text.encode(),
                            attachment=json.dumps({"chain_pos": row.chain_pos, "hash": row.hash}).encode())

    queryable = liar.declare_queryable("gaps/**", answer)
    looks_like_an_ingest = liar.declare_queryable(SYNC_KEY, lambda query: query.drop())
    try:
        report = fetch(tmp_path / "copy.db", FetchOptions("gaps/**", connect=(endpoint,)))
    finally:
        queryable.undeclare()
        looks_like_an_ingest.undeclare()
        liar.close()
    [chain] = report.chains
    assert chain.first_mismatch is not None and chain.first_mismatch.chain_pos == 1 and chain.match is False and report.exit_code == 1


def test_the_fetch_report_is_typed_and_prints_its_json_in_order(tmp_path):
    """The report's parts cross from the ingest to the command as frozen values (a refusal, an
    answer's error, a run's chain and its broken link), each printing the JSON keys `gaps fetch
    --json` has always printed, in that order; a foreign error reply keeps its own fields."""
    events = [make_event("vehicle/1", seq, "entity.state", run="run-x") for seq in range(2)]
    with Store(tmp_path / "honest.db") as store:
        store.append(events)
        rows = list(store.history("run-x"))
    endpoint = free_endpoint()
    liar = zenoh.open(session_config(listen=[endpoint]))

    def answer(query: zenoh.Query) -> None:
        with query:
            for row in rows:
                text = row.event.replace('"x":1.5', '"x":9.5') if row.chain_pos == 1 else row.event
                query.reply(f"gaps/run-x/{row.src}/{row.kind}", text.encode(),
                            attachment=json.dumps({"chain_pos": row.chain_pos, "hash": row.hash}).encode())
            query.reply("gaps/run-x/vehicle/1/entity.state", b"{not json")
            query.reply_err(json.dumps({"message": "busy", "error": "odd", "retry_s": 2}).encode())

    queryable = liar.declare_queryable("gaps/**", answer)
    looks_like_an_ingest = liar.declare_queryable(SYNC_KEY, lambda query: query.drop())
    try:
        report = fetch(tmp_path / "copy.db", FetchOptions("gaps/**", connect=(endpoint,)))
    finally:
        queryable.undeclare()
        looks_like_an_ingest.undeclare()
        liar.close()
    [refused], [error], [chain] = report.details, report.errors, report.chains
    assert isinstance(refused, Rejection) and isinstance(error, AnswerError) and isinstance(chain, ReceivedChain)
    assert isinstance(chain.first_mismatch, BrokenLink)
    for part in (refused, error, chain, chain.first_mismatch):
        with pytest.raises(AttributeError):
            part.run = "changed"            # type: ignore[misc,union-attr]
    assert (error.code, error.message) == ("odd", "busy")
    printed = report.to_json()
    assert list(printed) == ["key", "db", "received", "stored", "duplicates", "rejected", "details", "complete",
                             "errors", "pages", "responders", "chains", "elapsed_s", "exit_code"]
    assert printed["details"] == [{"origin": "gaps/run-x/vehicle/1/entity.state", "reason": refused.reason}]
    assert list(printed["errors"][0].items()) == [("message", "busy"), ("error", "odd"), ("retry_s", 2)]
    assert list(printed["chains"][0]) == ["run", "received", "first_chain_pos", "last_chain_pos", "source_head",
                                          "links_checked", "first_mismatch", "store_events", "store_head", "match"]
    assert list(printed["chains"][0]["first_mismatch"]) == ["chain_pos", "stated_hash", "recomputed"]
    assert (printed["chains"][0]["first_mismatch"]["chain_pos"], printed["exit_code"]) == (1, 1)


def test_nothing_answering_is_said_and_leaves_no_store(tmp_path):
    endpoint = free_endpoint()
    bare = zenoh.open(session_config(listen=[endpoint]))   # reachable, but no ingest there
    try:
        with pytest.raises(NothingAnswers, match="nothing answers history queries on gaps/.* no gaps serve"):
            fetch(tmp_path / "copy.db", FetchOptions("gaps/**", connect=(endpoint,), timeout_s=0.5))
    finally:
        bare.close()
    with pytest.raises(NothingAnswers, match="cannot reach"):
        fetch(tmp_path / "copy.db", FetchOptions("gaps/**", connect=(free_endpoint(),)))
    assert not (tmp_path / "copy.db").exists()


def test_gaps_fetch_on_the_command_line(source, tmp_path):
    endpoint, db = source
    before = file_sha(db)
    copy = tmp_path / "copy.db"
    result = gaps("fetch", "gaps/run-b/**", "--connect", endpoint, "--json", db=copy)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert (summary["received"], summary["stored"], summary["complete"]) == (60, 60, True)
    assert [c["match"] for c in summary["chains"]] == [True]
    text = gaps("fetch", "gaps/run-b/**", "--connect", endpoint, db=copy)
    assert text.exit_code == 0 and "run run-b: the chain matches the sender's over its first 60 events" in text.stdout
    assert gaps("fetch", "gaps/**", "--connect", endpoint, "--from", "12s", db=copy).exit_code == 2
    nobody = gaps("fetch", "gaps/**", "--connect", free_endpoint(), db=tmp_path / "none.db")
    assert nobody.exit_code == 3 and "cannot reach" in nobody.stderr
    assert gaps("fetch", "other/**", "--connect", endpoint, db=copy).exit_code == 2
    assert file_sha(db) == before   # answering reads the source store without changing it
