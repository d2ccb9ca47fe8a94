"""Monitor observations are state for OBSERVATION_WINDOW_S: the same answer with and without
snapshots, however the snapshots fall, and old observations never reach a reader."""
from __future__ import annotations

import random

from store import Store
from store import timeline as timeline_module
from store.state import OBSERVATION_WINDOW_S, build_snapshots, state_at
from store.timeline import Timeline
from tests.helpers.store_testkit import T0

S = 1_000_000_000


def observations(n: int, seed: int) -> list[dict]:
    """Two monitors observing five vehicles now and then over a minute (gaps longer than the window)."""
    rng = random.Random(seed)
    seqs: dict[str, int] = {}
    out = []
    for t in sorted(rng.randrange(0, 60 * S) for _ in range(n)):
        src = rng.choice(["monitor/m1", "monitor/m2"])
        seq = seqs.get(src, 0)
        seqs[src] = seq + 1
        vehicle = str(rng.randrange(5))
        out.append({"v": 1, "run": "r", "src": src, "seq": seq, "t": T0 + t, "kind": "monitor.observation",
                    "body": {"vehicle": vehicle, "facts": [f"{vehicle} has red light"]}})
    return out


def test_observations_older_than_the_window_are_not_state(tmp_path):
    events = observations(40, 1)
    with Store(tmp_path / "s.db") as store:
        store.append(events)
        for t in [T0 + k * S // 2 for k in range(0, 130)]:
            got = state_at(store, "r", t, use_snapshots=False)
            for src, monitor in got.monitors.items():
                for vehicle, piece in monitor["observations"].items():
                    assert t - OBSERVATION_WINDOW_S * S <= piece["t"] <= t
                    # and it is the latest observation of that vehicle by that monitor
                    latest = max(e["t"] for e in events if e["src"] == src and e["body"]["vehicle"] == vehicle
                                 and e["t"] <= t)
                    assert piece["t"] == latest
            seen = {(src, v) for src, m in got.monitors.items() for v in m["observations"]}
            fresh = {(e["src"], e["body"]["vehicle"]) for e in events
                     if t - OBSERVATION_WINDOW_S * S <= e["t"] <= t}
            assert seen == fresh


def test_pruned_snapshots_give_the_answers_of_a_fold_from_the_start(tmp_path, monkeypatch):
    monkeypatch.setattr(timeline_module, "MAX_STEP", 3)
    events = observations(120, 2)
    with Store(tmp_path / "s.db") as store:
        store.append(events)
        build_snapshots(store, "r", every=7)
        line, rng = Timeline(store, "r"), random.Random(3)
        for t in sorted(rng.randrange(T0 - S, T0 + 70 * S) for _ in range(60)):
            want = state_at(store, "r", t, use_snapshots=False)
            assert state_at(store, "r", t) == want
            assert line.at(t) == want
