"""Sequence gaps looked up for the reasoner: one check of the whole run first, per source after."""
from __future__ import annotations

from reasoner.findings import Gaps
from store import Store

T0 = 1_732_176_000_000_000_000


def events(drop: set[tuple[str, int]] = frozenset()) -> list[dict]:
    out = []
    for src in ("vehicle/1", "vehicle/2", "monitor/m1"):
        for seq in range(20):
            if (src, seq) in drop:
                continue
            kind, body = (("monitor.observation", {"vehicle": "1", "facts": ["1 is stopped"]})
                          if src.startswith("monitor") else ("entity.state", {"x": 0.0, "y": 0.0, "speed_mps": 1.0}))
            out.append({"v": 1, "run": "r", "src": src, "seq": seq, "t": T0 + seq, "kind": kind, "body": body})
    return out


def test_a_run_without_gaps_needs_no_source_read(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(events())
        gaps = Gaps(store, "r")
        assert gaps.of("vehicle/1") == [] and gaps.of("monitor/m1") == []
        assert gaps._found == {}            # the run-wide check said no source has a gap


def test_gaps_are_found_in_the_source_that_has_them(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(events(drop={("vehicle/2", 5), ("vehicle/2", 6), ("vehicle/2", 19), ("monitor/m1", 0)}))
        gaps = Gaps(store, "r")
        assert gaps.of("vehicle/1") == []
        assert gaps.of("vehicle/2") == [(5, 6)]       # a missing last event is not a gap to see
        assert gaps.of("monitor/m1") == [(0, 0)]
