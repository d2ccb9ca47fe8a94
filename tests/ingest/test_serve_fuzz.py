"""A hostile publisher against a running `gaps serve`, over real Zenoh on loopback: random bytes,
random JSON, broken envelopes, unknown kinds, foreign encodings, keys that disagree with the body,
duplicates (identical and conflicting), an oversized event, mixed with valid events. The service
must stay up; every refused sample must be in quarantine with its exact bytes; every valid event
must be stored once; and its counters must agree."""
from __future__ import annotations

import itertools
import json
from collections import Counter
from pathlib import Path

import zenoh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sim_replay.publisher import EventPublisher, zenoh_config
from store import MAX_EVENT_BYTES, Store, canonical_json
from store.wire import key_for
from tests.helpers.ingest_testkit import BODIES, RUN, free_endpoint, make_event
from tests.helpers.serve_testkit import ServeProcess

CHUNK = st.from_regex(r"[A-Za-z0-9_-][A-Za-z0-9._-]{0,11}", fullmatch=True)
JSON_VALUES = st.recursive(st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(),
                           lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(), inner, max_size=4),
                           max_leaves=12)
BROKEN_FIELDS = {
    "v": st.integers().filter(lambda v: v != 1) | st.text(),
    "seq": st.integers(max_value=-1) | st.text() | st.floats(allow_nan=False),
    "t": st.text() | st.none() | st.lists(st.integers(), max_size=2),
    "body": st.text() | st.integers() | st.lists(st.integers(), max_size=3),
    "run": st.text(min_size=1).filter(lambda r: not r.replace(".", "").replace("_", "").replace("-", "").isalnum()),
}
FOREIGN_ENCODINGS = ["application/cbor", "application/protobuf", "image/png", "text/plain"]

RECIPES = st.one_of(
    st.tuples(st.just("valid"), st.sampled_from(sorted(BODIES)), st.integers(0, 7)),
    st.tuples(st.just("duplicate"), st.booleans()),             # resent: the same bytes, or re-spaced JSON
    st.tuples(st.just("conflict"), st.text(min_size=1, max_size=20)),
    st.tuples(st.just("wrong_key"), st.integers(0, 7)),
    st.tuples(st.just("encoding"), st.sampled_from(FOREIGN_ENCODINGS)),
    st.tuples(st.just("unknown_kind"), st.from_regex(r"[a-z]{1,8}\.[a-z]{1,8}", fullmatch=True)),
    st.tuples(st.just("bytes"), st.lists(CHUNK, min_size=1, max_size=4), st.binary(max_size=300)),
    st.tuples(st.just("json"), st.lists(CHUNK, min_size=1, max_size=4), JSON_VALUES),
    st.tuples(st.just("broken"), st.sampled_from(sorted(BROKEN_FIELDS)), st.data()),
    st.tuples(st.just("missing"), st.sampled_from(["v", "run", "src", "seq", "t", "kind", "body"])),
    st.tuples(st.just("duplicate_key"),),
)


class Ledger:
    """What was sent and what each sample must become: stored, a duplicate, or quarantined as sent."""

    def __init__(self, publisher: EventPublisher) -> None:
        self.publisher = publisher
        self.seqs = itertools.count()
        self.valid: list[dict] = []
        self.duplicates = 0
        self.refused: Counter[tuple[str, bytes]] = Counter()
        self.sent = 0

    def put(self, key: str, payload: bytes, *, encoding: str = "application/json") -> None:
        self.publisher.session.put(key, payload, encoding=zenoh.Encoding(encoding),
                                   congestion_control=zenoh.CongestionControl.BLOCK)
        self.sent += 1

    def refuse(self, key: str, payload: bytes, **how: str) -> None:
        self.put(key, payload, **how)
        self.refused[(key, payload)] += 1

    def fresh(self, kind: str = "vehicle.perception", source: int = 0) -> dict:
        """A valid event from a source of the role its kind needs (a signal sends signal.state)."""
        role = {"signal.state": "signal", "monitor.observation": "monitor"}.get(kind, "vehicle")
        return make_event(f"{role}/{source}", next(self.seqs), kind)

    def follow(self, recipe: tuple) -> None:
        """Send what one recipe describes, and note what it must become."""
        what, *args = recipe
        if what == "valid" or (what in ("duplicate", "conflict") and not self.valid):
            kind, source = (args if what == "valid" else ("entity.state", 1))
            event = self.fresh(kind, source)
            self.put(key_for(event), canonical_json(event))
            self.valid.append(event)
        elif what == "duplicate":
            earlier = self.valid[-1]
            self.put(key_for(earlier), canonical_json(earlier) if args[0] else json.dumps(earlier, indent=1).encode())
            self.duplicates += 1
        elif what == "conflict":
            changed = {**self.valid[-1], "body": {**self.valid[-1]["body"], "note": args[0]}}
            self.refuse(key_for(changed), canonical_json(changed))
        else:
            self._hostile(what, args)

    def _hostile(self, what: str, args: list) -> None:
        event = self.fresh()
        key, payload, how = key_for(event), canonical_json(event), {}
        if what == "wrong_key":
            key = key_for({**event, "src": f"vehicle/other{args[0]}"})
        elif what == "encoding":
            how = {"encoding": args[0]}
        elif what == "unknown_kind":
            event["kind"] = args[0]
            key, payload = key_for(event), canonical_json(event)
        elif what in ("bytes", "json"):
            key = "gaps/" + "/".join(args[0])
            payload = args[1] if what == "bytes" else json.dumps(args[1]).encode()
        elif what == "broken":
            event[args[0]] = args[1].draw(BROKEN_FIELDS[args[0]])
            payload = json.dumps(event).encode()
        elif what == "missing":
            del event[args[0]]
            payload = json.dumps(event).encode()
        elif what == "duplicate_key":
            payload = b'{"seq": 0, ' + payload[1:]
        self.refuse(key, payload, **how)


def test_hostile_publisher_cannot_stop_serve_or_lose_a_sample(tmp_path: Path) -> None:
    db = tmp_path / "gaps.db"
    endpoint = free_endpoint()
    serve = ServeProcess(db, endpoint, "--json")
    try:
        serve.wait_for_log("serve.ready")
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            ledger = Ledger(publisher)
            first = ledger.fresh()
            assert publisher.wait_until_matched(first, 10)
            ledger.put(key_for(first), canonical_json(first))
            ledger.valid.append(first)
            huge = ledger.fresh()
            huge["body"]["facts"] = ["173 has red light " * (MAX_EVENT_BYTES // 16)]
            ledger.refuse(key_for(huge), canonical_json(huge))

            @settings(max_examples=40, deadline=None, database=None,
                      suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
            @given(st.lists(RECIPES, min_size=1, max_size=12))
            def attack(recipes: list[tuple]) -> None:
                for recipe in recipes:
                    ledger.follow(recipe)
                assert publisher.sync(30) == 1, "gaps serve stopped answering"
                assert serve.proc.poll() is None, serve.lines[-5:]

            attack()
        code, out = serve.stop()
    finally:
        serve.kill()
    metrics = json.loads(out)
    assert code == 0 and metrics["failed"] == 0 and metrics["errors"] == 0, metrics
    assert metrics["received"] == ledger.sent
    assert (metrics["stored"], metrics["duplicates"], metrics["quarantined"]) == (
        len(ledger.valid), ledger.duplicates, sum(ledger.refused.values()))
    with Store.open_read_only(db) as store:
        assert store.verify().ok
        assert sorted(canonical_json(e) for e in store.events(RUN)) == sorted(canonical_json(e) for e in ledger.valid)
        kept: Counter = Counter()
        for q in store.quarantined():  # identical refusals are one row with a count (store/quarantine.py)
            kept[(q["origin"], q["raw"])] += q["count"]
        assert all(q["reason"] for q in store.quarantined())
    assert kept == ledger.refused
