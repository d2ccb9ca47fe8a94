"""A Timeline's states at rising (and falling) times equal state_at's."""
from __future__ import annotations

import random

from store import Store
from store import timeline as timeline_module
from store.state import state_at
from store.timeline import Timeline
from tests.helpers.store_testkit import T0
from test_store_kind_index import mixed_events


def test_timeline_states_equal_state_at(tmp_path, monkeypatch):
    monkeypatch.setattr(timeline_module, "MAX_STEP", 25)    # so that both steps and jumps happen
    events = mixed_events(300, 3)
    with Store(tmp_path / "s.db") as store:
        store.append(events)
        line = Timeline(store, "r")
        rng = random.Random(4)
        times = sorted(rng.randrange(T0 - 10, T0 + 60_000) for _ in range(40))
        times += [T0 + 5_000, T0 + 100]          # backwards too
        for t in times:
            got = line.at(t)
            assert got == state_at(store, "r", t), t
        assert line.steps > 0 and line.jumps > 1


def test_a_state_handed_out_stays_as_it_was_when_the_timeline_moves_on(tmp_path):
    events = mixed_events(300, 3)
    with Store(tmp_path / "s.db") as store:
        store.append(events)
        line = Timeline(store, "r")
        rng = random.Random(5)
        times = sorted(rng.randrange(T0, T0 + 60_000) for _ in range(30))
        kept = [(line.at(t), state_at(store, "r", t)) for t in times]
        assert line.steps > 0
        for got, want in kept:
            assert got == want, got.t
