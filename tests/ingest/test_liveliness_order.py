"""The liveliness race, made deterministic: a source's token appears and disappears on its own
Zenoh channel while its events wait in another (the inbox), so the writer learns of a change
between two takes of events, not at its place among them. Here the writer (ingest/writer.py) is
driven through its own seams, an inbox and a wire watch that hand over exactly the scripted
batches and changes, so each ordering is exercised every run, with no sleeps and no Zenoh.

What must hold: every appearance and disappearance is recorded, in the order noticed; a
disappearance is placed after every event of its source received before it (never before its
last events, however many were queued); an appearance is placed before every event received
after it (never after events its source sent once it had appeared); and no event is lost or
stored under another source."""
from __future__ import annotations

import time
from pathlib import Path
from types import SimpleNamespace

from ingest.gap_tracker import GapTracker
from ingest.inbox import Received
from ingest.stats import IngestStats
from ingest.wire_watch import Noticed
from ingest.writer import BatchWriter
from store import Store, canonical_json
from store.wire import LivelinessChange, key_for
from tests.helpers.ingest_testkit import RUN, make_event

FULL = 4   # the writer's batch size here: a take of 4 means more were waiting (not caught up)

Step = tuple[list[tuple[str, int]], list[tuple[str, bool]]]
"""One take: the events (src, seq) it hands over, and the token changes (src, appeared) that
reach the liveliness channel while it runs, i.e. before the writer's next look at that channel."""


def _sample(src: str, seq: int) -> Received:
    event = make_event(src, seq, "entity.state")
    return key_for(event), canonical_json(event), True, "application/json"


class ScriptedWire:
    """The inbox and the wire watch at once: each take hands over the next step's events and puts
    its token changes where the next drain finds them; after the last step the inbox is closed."""

    closing = False
    first_at = 0.0

    def __init__(self, steps: list[Step]) -> None:
        self._steps = list(steps)
        self._arrived: list[tuple[str, bool]] = []
        self.recovery = SimpleNamespace(stored_highest=None, saw=lambda *args: None)

    def take(self, max_items: int, wait_s: float) -> list[Received] | None:
        if not self._steps:
            return None
        events, changes = self._steps.pop(0)
        assert len(events) <= max_items
        self.first_at = time.monotonic()
        self._arrived.extend(changes)
        return [_sample(src, seq) for src, seq in events]

    def drain(self, highest_seq) -> Noticed:
        """As WireWatch.drain: each change with its source's place as ``highest_seq`` says."""
        arrived, self._arrived = self._arrived, []
        return Noticed(tuple(LivelinessChange(RUN, src, alive, time.time_ns(), highest_seq(RUN, src))
                             for src, alive in arrived))

    def recovered(self, max_items: int) -> list[Received]:
        return []


def _run(db: Path, steps: list[Step]) -> list[tuple[str, bool, int | None]]:
    """Drive a writer through the steps to the end; the changes recorded, in order."""
    wire = ScriptedWire(steps)
    writer = BatchWriter(db, wire, IngestStats(), GapTracker(), batch_size=FULL, flush_interval_s=0.0,
                         durable=False, watch=wire)
    writer.start()
    writer.join(30)
    assert not writer.is_alive()
    with Store.open_read_only(db) as store:
        return [(c.src, c.alive, c.last_seq) for c in store.liveliness_changes(RUN)]


def _events(db: Path) -> list[tuple[str, int]]:
    """(src, seq) of every event stored, sorted; the chain verified."""
    with Store.open_read_only(db) as store:
        assert store.verify(RUN).ok
        return sorted((e["src"], e["seq"]) for e in store.events(RUN))


A, B = "vehicle/1", "vehicle/2"


def test_a_token_gone_while_its_events_are_queued_is_placed_after_them(db_path: Path) -> None:
    steps = [([(A, 0), (A, 1), (A, 2), (A, 3)], [(A, False)]),    # gone after seq 5, noticed at seq 3
             ([(A, 4), (A, 5)], [])]                               # the queue runs dry: caught up
    assert _run(db_path, steps) == [(A, False, 5)]
    assert _events(db_path) == [(A, seq) for seq in range(6)]


def test_a_token_that_appears_before_its_first_event_is_placed_before_it(db_path: Path) -> None:
    steps = [([(A, 0), (A, 1), (A, 2), (A, 3)], [(A, True)]),     # declared before seq 0, noticed after 3
             ([(A, 4)], [])]
    assert _run(db_path, steps) == [(A, True, None)]


def test_a_token_that_appears_after_its_first_events_is_placed_after_those_written_before(db_path: Path) -> None:
    steps = [([(B, 0), (B, 1)], []),                              # heard before its token (an ingest started late)
             ([(B, 2), (B, 3), (B, 4), (B, 5)], [(B, True)]),
             ([], [])]
    assert _run(db_path, steps) == [(B, True, 1)]


def test_gone_and_back_are_both_recorded_in_order_each_at_its_place(db_path: Path) -> None:
    steps = [([(A, 0), (A, 1)], [(A, True)]),
             ([(A, 2), (A, 3), (A, 4), (B, 0)], [(A, False)]),    # A's producer died after seq 4
             ([(B, 1)], []),                                       # caught up: A's end is recorded
             ([], [(A, True)]),                                    # a new producer for A appears...
             ([(A, 5), (A, 6), (A, 7), (A, 8)], []),               # ...and goes on: a backlog
             ([(A, 9)], [(A, False)]),
             ([], [])]
    assert _run(db_path, steps) == [(A, True, None), (A, False, 4), (A, True, 4), (A, False, 9)]
    assert _events(db_path) == [*((A, seq) for seq in range(10)), (B, 0), (B, 1)]


def test_changes_noticed_at_the_last_look_are_all_recorded(db_path: Path) -> None:
    steps = [([(A, 0), (B, 0), (A, 1), (B, 1)], [(A, True), (B, True), (A, False)])]
    assert _run(db_path, steps) == [(A, True, None), (B, True, None), (A, False, 1)]
