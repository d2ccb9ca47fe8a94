"""What the ingest asks the producers' caches for (ingest/cache_recovery.py), seen from the queries
it sends: the holes of a batch in one query, a cache's index followed above each source's stored
seq for the sources not heard live, nothing for a slice by kind. The session is a recorder here;
tests/ingest/test_producer_cache.py runs the same over Zenoh."""
from __future__ import annotations

import json
from types import SimpleNamespace

import zenoh

from ingest.cache_recovery import CacheRecovery
from store.wire import SourceSpan, write_index

CACHE = "0123456789abcdef0123456789abcdef"


class Replies:
    """A query's handler: the replies given, then closed (every reply is in)."""

    def __init__(self, replies: list) -> None:
        self._replies = list(replies)

    def try_recv(self):
        if self._replies:
            return self._replies.pop(0)
        raise zenoh.ZError("closed")


class Session:
    """Records each query (selector, want list) and answers with the replies queued for it."""

    def __init__(self) -> None:
        self.asked: list[tuple[str, list | None]] = []
        self.answers: list[list] = []

    def get(self, selector: str, handler: object, *, payload: bytes | None = None, **options: object) -> Replies:
        self.asked.append((selector, json.loads(payload)["want"] if payload else None))
        return Replies(self.answers.pop(0) if self.answers else [])

    def is_closed(self) -> bool:
        return False


def _index_reply(spans: list[SourceSpan]) -> SimpleNamespace:
    ok = SimpleNamespace(payload=SimpleNamespace(to_bytes=lambda: write_index(spans)),
                         key_expr=f"gaps/@cache/{CACHE}")
    return SimpleNamespace(ok=ok, err=None)


def _recovery(key: str = "gaps/**", stored: dict | None = None) -> tuple[CacheRecovery, Session]:
    session = Session()
    recovery = CacheRecovery(session, key)
    recovery.stored_highest = lambda run, src: (stored or {}).get((run, src))
    return recovery, session


def test_the_holes_of_a_batch_are_asked_in_one_query_above_what_is_stored() -> None:
    recovery, session = _recovery(stored={("r", "vehicle/1"): 9})
    for src, seq in [("vehicle/1", 15), ("vehicle/2", 0), ("vehicle/2", 1), ("vehicle/3", 4), ("vehicle/1", 16)]:
        recovery.saw("r", src, seq, live=True)
    assert not recovery.idle
    recovery.step()
    assert session.asked == [("gaps/@cache/*/**", [["r", "vehicle/1", 10, 14], ["r", "vehicle/3", 0, 3]])]
    assert recovery.recovered(100) == [] and recovery.idle


def test_a_cache_found_is_asked_its_index_then_what_the_unheard_sources_lack() -> None:
    recovery, session = _recovery(stored={("r", "vehicle/1"): 40, ("r", "vehicle/2"): 7})
    recovery.saw("r", "vehicle/3", 0, live=True)                   # heard live: followed by its seqs
    session.answers.append([_index_reply([SourceSpan("r", "vehicle/1", 30, 50), SourceSpan("r", "vehicle/2", 0, 7),
                                          SourceSpan("r", "vehicle/3", 0, 2), SourceSpan("r", "vehicle/4", 5, 9)])])
    recovery.on_token(SimpleNamespace(key_expr=f"gaps/@cache/{CACHE}", kind=zenoh.SampleKind.PUT))
    assert not recovery.idle
    recovery.step()
    assert session.asked == [
        (f"gaps/@cache/{CACHE}/**?_index", None),
        (f"gaps/@cache/{CACHE}/**", [["r", "vehicle/1", 41, 50], ["r", "vehicle/4", 0, 9]]),
    ]
    recovery.saw("r", "vehicle/1", 51, live=True)                  # the live stream goes on: no hole
    recovery.step()
    assert len(session.asked) == 2


def test_a_slice_by_kind_asks_no_holes_and_its_index_within_its_key() -> None:
    recovery, session = _recovery(key="gaps/**/entity.state")
    recovery.saw("r", "vehicle/1", 5, live=True)
    recovery.on_token(SimpleNamespace(key_expr=f"gaps/@cache/{CACHE}", kind=zenoh.SampleKind.PUT))
    recovery.step()
    assert session.asked == [(f"gaps/@cache/{CACHE}/**/entity.state?_index", None)]


def test_a_batch_followed_in_one_loop_asks_the_holes_its_seqs_leave_in_order() -> None:
    """saw_all, the writer's road for a batch: every hole above what was known, per source, as
    the seqs come (a late seq fills nothing and opens nothing); cache replies (not live) open none."""
    recovery, session = _recovery(stored={("r", "vehicle/1"): 9})
    recovery.saw_all([("r", "vehicle/1", 12), ("r", "vehicle/2", 3), ("r", "vehicle/1", 11), ("r", "vehicle/1", 20),
                      ("r", "vehicle/2", 4), ("r", "vehicle/2", 7)], live=True)
    recovery.saw_all([("r", "vehicle/3", 50)], live=False)
    recovery.saw_all([("r", "vehicle/3", 52)], live=True)
    recovery.step()
    assert session.asked == [("gaps/@cache/*/**", [["r", "vehicle/1", 10, 11], ["r", "vehicle/2", 0, 2],
                                                   ["r", "vehicle/1", 13, 19], ["r", "vehicle/2", 5, 6],
                                                   ["r", "vehicle/3", 51, 51]])]
