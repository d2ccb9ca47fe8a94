"""Verify on a store being appended to: one snapshot per verify, so never a false alarm.

Checkpoints are written in the same transaction as the events they cover. A verify that read the
checkpoints in one snapshot and the events in a later one saw events "not covered by any
checkpoint" whenever a writer committed in between (issue 15, finding 5: once in 61 runs).
"""
from __future__ import annotations

import sqlite3
import threading

from store import Store
from store.verify import verify_store
from tests.helpers.store_testkit import event

SRC = "vehicle/1"


def _appender(writer: Store, start: int, every: int = 20):
    """A progress handler for the reading connection: every 4 * `every` SQLite steps of the
    verify, the writer commits three more events (and their checkpoint) from another connection."""
    state = {"next": start, "commits": 0, "calls": 0}

    def handler() -> int:
        state["calls"] += 1
        if state["calls"] % 4 == 0 and state["commits"] < 20:
            writer.append([event(state["next"] + k, src=SRC) for k in range(3)])
            state["next"] += 3
            state["commits"] += 1
        return 0
    return handler, state, every


def test_a_commit_in_the_middle_of_verify_is_not_seen_by_it(db_path):
    """Deterministic: the writer commits while verify is between its reads. Without one read
    transaction around the whole verify this fails ("not covered by any checkpoint")."""
    with Store(db_path, durable=False) as writer:
        writer.append([event(i, src=SRC) for i in range(30)])
        reader = sqlite3.connect(f"file:{db_path}?mode=ro", uri=True, isolation_level=None)
        try:
            handler, state, every = _appender(writer, 30)
            reader.set_progress_handler(handler, every)
            report = verify_store(reader, integrity=lambda conn: [])  # the commits fall among the chain reads
            reader.set_progress_handler(None, 0)
            assert report.ok, report.problem
            seen, total = report.runs[0].events, 30 + 3 * state["commits"]
            assert state["commits"] >= 5 and seen < total  # commits came after verify's snapshot began
            assert verify_store(reader).runs[0].events == total
        finally:
            reader.close()


def test_verify_while_a_writer_appends_never_fails(db_path):
    """A writer thread appending small batches while a reader verifies again and again."""
    with Store(db_path, durable=False, check_same_thread=False) as writer:
        writer.append([event(i, src=SRC) for i in range(50)])
        stop = threading.Event()
        errors: list[BaseException] = []

        def append_until_stopped() -> None:
            seq = 50
            try:
                while not stop.is_set() and seq < 3000:
                    writer.append([event(seq + k, src=SRC) for k in range(3)])
                    seq += 3
                    stop.wait(0.001)
            except BaseException as exc:  # pragma: no cover - reported below
                errors.append(exc)

        thread = threading.Thread(target=append_until_stopped)
        thread.start()
        problems, counts = [], []
        try:
            with Store.open_read_only(db_path) as reader:
                for _ in range(15):
                    report = reader.verify()
                    counts.append(report.runs[0].events)
                    if not report.ok:
                        problems.append(report.problem)
        finally:
            stop.set()
            thread.join()
        assert not errors
        assert problems == []
        assert counts[-1] > counts[0]  # the store did grow while it was verified
