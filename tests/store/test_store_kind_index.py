"""Reads by kind: the partial index over the sparse kinds, and merged reads of several kinds."""
from __future__ import annotations

import random

from store import Store
from store.ddl import DENSE_KINDS
from store.queries import select_events
from tests.helpers.store_testkit import BODIES, SOURCES, T0

KINDS = sorted(BODIES)


def mixed_events(n: int, seed: int) -> list[dict]:
    """n events of every kind from their sources, times shuffled so kinds interleave."""
    rng = random.Random(seed)
    seqs: dict[str, int] = {}
    out = []
    for _ in range(n):
        kind = rng.choice(KINDS)
        src = SOURCES.get(kind, "vehicle/173")
        seq = seqs.get(src, 0)
        seqs[src] = seq + 1
        out.append({"v": 1, "run": "r", "src": src, "seq": seq, "t": T0 + rng.randrange(0, 50) * 1000,
                    "kind": kind, "body": BODIES[kind]})
    return out


def plan(store: Store, kinds: list[str]) -> str:
    sql, params = select_events("r", kinds, None, None, None)
    return " ".join(str(row[-1]) for row in store.connection.execute("EXPLAIN QUERY PLAN " + sql, params))


def test_a_sparse_kind_is_read_through_the_kind_index(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(mixed_events(50, 1))
        assert "events_by_kind" in plan(store, ["monitor.observation"])
        assert "events_by_kind" not in plan(store, ["entity.state"])   # dense kinds are not in it


def test_reads_by_kinds_match_a_filter_of_all_events_in_order(tmp_path):
    events = mixed_events(400, 2)
    with Store(tmp_path / "s.db") as store:
        store.append(events)
        everything = list(store.events("r"))
        for kinds in (["monitor.observation"], ["ads.event", "monitor.observation", "vehicle.decision"],
                      ["entity.state", "signal.state"], list(DENSE_KINDS), KINDS):
            got = [(e["t"], e["seq"], e["src"]) for e in store.events("r", kinds=kinds)]
            want = [(e["t"], e["seq"], e["src"]) for e in everything if e["kind"] in kinds]
            assert got == want, kinds
            t_to = T0 + 20_000
            got = [e["seq"] for e in store.events("r", kinds=kinds, t_to=t_to, srcs=["monitor/m1"])]
            want = [e["seq"] for e in everything if e["kind"] in kinds and e["t"] <= t_to and e["src"] == "monitor/m1"]
            assert got == want, kinds
