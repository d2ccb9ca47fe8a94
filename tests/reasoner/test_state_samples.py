"""A run's entity.state samples kept per source (reasoner/state_samples.py): any sequence of
windows asked gives, each time, exactly what one read of that window gives (the events in it, in
(t, seq) order, cut after `cap`), with the notes on events that carried no measurement; and what
is kept stays under its bound."""

import tempfile
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st
from tests.helpers.store_testkit import T0, event

from reasoner.history import samples
from reasoner.history import StateSamples
from store import Store

MS = 1_000_000
SRCS = ["vehicle/1", "vehicle/2"]

states = st.lists(st.tuples(st.sampled_from(SRCS), st.integers(0, 300), st.integers(-2, 2),
                            st.sampled_from(["ok", "ok", "ok", "no speed", "nan x"])), max_size=80)
windows = st.lists(st.tuples(st.sampled_from(SRCS), st.integers(-500, 9_000), st.integers(0, 4_000),
                             st.integers(1, 40)), min_size=1, max_size=12)


def build(picks) -> list[dict]:
    """States with t rising with seq by 100 ms steps, a few places out of order, some of them
    without a speed or with a position that is not a number."""
    seqs: dict[str, int] = {}
    out = []
    for src, step, jitter, shape in picks:
        seq = seqs[src] = seqs.get(src, -1) + 1
        body = {"x": 1.0 + seq, "y": -2.0, "speed_mps": 8.25}
        if shape == "no speed":
            del body["speed_mps"]
        elif shape == "nan x":
            body["x"] = "NaN"
        out.append(event(seq, src=src, t=T0 + max(0, seq * 100 + jitter * 100 + step) * MS, kind="entity.state",
                         body=body))
    return out


def direct(store, src, t_from, t_to, cap):
    events = store.source_events("r1", src, kinds=["entity.state"], t_from=t_from, t_to=t_to)
    found, notes = samples(events[:cap])
    return found, notes, len(events)


@settings(max_examples=80, deadline=None)
@given(picks=states, asked=windows, max_kept=st.sampled_from([1, 10, 1000]))
def test_every_window_is_what_one_read_of_it_gives(picks, asked, max_kept):
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "s.db") as store:
        store.append(build(picks))
        kept = StateSamples(store, "r1", max_kept=max_kept)
        for src, start_ms, length_ms, cap in asked:
            t_from = T0 + start_ms * MS
            t_to = t_from + length_ms * MS
            window = kept.window(src, t_from, t_to, cap)
            assert (window.samples, window.notes, window.events) == direct(store, src, t_from, t_to, cap)


def test_a_window_before_what_is_kept_and_one_across_it():
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "s.db") as store:
        store.append(build([("vehicle/1", 0, 0, "ok")] * 30))
        kept = StateSamples(store, "r1")
        for start_ms, end_ms in ((1000, 2000), (500, 1500), (0, 600), (300, 2900), (2800, 3000)):
            t_from, t_to = T0 + start_ms * MS, T0 + end_ms * MS
            assert (w := kept.window("vehicle/1", t_from, t_to, 100)).events > 0
            assert (w.samples, w.notes, w.events) == direct(store, "vehicle/1", t_from, t_to, 100)


def test_what_is_kept_is_let_go_past_its_bound():
    picks = [(src, 0, 0, "ok") for _ in range(50) for src in SRCS]
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "s.db") as store:
        store.append(build(picks))
        kept = StateSamples(store, "r1", max_kept=60)
        for src in SRCS:
            assert kept.window(src, T0, T0 + 10_000 * MS, 1000).events == 50
        assert list(kept._kept) == ["vehicle/2"] and kept._size == 50
