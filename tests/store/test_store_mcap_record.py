"""A producer's live recording (store.Recorder): events as they come, written in log time with
the same channels and drawing as an export, readable by the official reader, importable."""

from __future__ import annotations

import pytest
from mcap.reader import make_reader

from store import Store, canonical_json
from store.transfer import Recorder, TransferError, import_file
from tests.helpers.viewer_run import RUN, viewer_events

S = 1_000_000_000


def _messages(path):
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        return summary, [(channel.topic, message.log_time, message.data)
                         for _, channel, message in reader.iter_messages(log_time_order=False)]


def test_events_arriving_out_of_order_within_the_window_are_written_in_log_time_and_import_back(tmp_path):
    events = viewer_events()              # in arrival order, not time order (one source 50 ms late)
    assert [e["t"] for e in events] != sorted(e["t"] for e in events)
    path = tmp_path / "run.mcap"
    with Recorder(path) as rec:
        for e in events:
            rec.add(e)
    assert rec.late == 0 and rec.report.events == len(events) and rec.report.derived > 0
    summary, messages = _messages(path)
    times = [t for _, t, _ in messages]
    assert times == sorted(times)                                   # file order is log-time order
    assert summary.statistics.message_count == len(messages)
    recorded = sorted(m[2] for m in messages if m[0].startswith(f"gaps/{RUN}/"))
    assert recorded == sorted(canonical_json(e) for e in events)    # every event, byte for byte
    with Store(tmp_path / "s.db") as store:
        report = import_file(store, path)
        assert report.stored == len(events) and not report.rejected
        stored = sorted(canonical_json(e) for e in store.events(RUN))
    assert stored == recorded


def test_an_event_later_than_the_window_is_kept_and_counted_late(tmp_path):
    events = sorted(viewer_events(), key=lambda e: e["t"])
    late = events.pop(3)
    path = tmp_path / "run.mcap"
    with Recorder(path, window_s=0.5) as rec:
        for e in events:
            rec.add(e)
        rec.add(late)
    assert rec.late == 1 and rec.report.events == len(events) + 1
    _, messages = _messages(path)
    assert canonical_json(late) in [m[2] for m in messages]


def test_a_recording_that_fails_leaves_what_was_there(tmp_path):
    path = tmp_path / "run.mcap"
    path.write_bytes(b"an earlier recording")
    with pytest.raises(RuntimeError):
        with Recorder(path) as rec:
            rec.add(viewer_events()[0])
            raise RuntimeError("the simulation stopped")
    assert path.read_bytes() == b"an earlier recording"
    assert [p.name for p in tmp_path.iterdir()] == ["run.mcap"]     # no partial file left


def test_one_run_per_recording_and_envelopes_only(tmp_path):
    first = viewer_events()[0]
    with pytest.raises(TransferError, match="one run"):
        with Recorder(tmp_path / "a.mcap") as rec:
            rec.add(first)
            rec.add({**first, "run": "another", "seq": 99})
    with pytest.raises(TransferError, match="not an event envelope"):
        with Recorder(tmp_path / "b.mcap") as rec:
            rec.add({"run": RUN, "src": "vehicle/1", "seq": "0", "t": 1, "kind": "entity.state"})


def test_a_recording_gets_the_permissions_any_new_file_gets(tmp_path):
    import os
    mask = os.umask(0o022)
    try:
        with Recorder(tmp_path / "run.mcap") as rec:
            rec.add(viewer_events()[0])
    finally:
        os.umask(mask)
    assert (tmp_path / "run.mcap").stat().st_mode & 0o777 == 0o644
