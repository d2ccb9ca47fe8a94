"""explain/evidence.py reads the run's chain status and the cited events as values: the store's
Problem (the first link that failed) through reasoner.ChainStatus, and store.EventRefs, a proof
tree's evidence (DESIGN's JSON) read as one at the edge. The JSON an explanation prints is the
same as when they were dicts: the problem as the store states it, {} for a failure naming no link."""
from reasoner import ChainStatus
from store import EventRef, Problem

from explain.evidence import EvidenceIndex, chain_json, chain_text

RUN = "r1"
SPAWN = EventRef(RUN, "vehicle/7", 0, 1_000, "entity.spawn")
STATE = {"run": RUN, "src": "vehicle/7", "seq": 1, "t": 2_000, "kind": "entity.state"}     # a tree's evidence
PV = EventRef(RUN, "monitor/m1", 4, 2_000, "monitor.potential_violation")


class Positions:
    """A store's chain_positions: the spawn at 10, the state at 11, the potential violation at 12."""

    def chain_positions(self, run, keys):
        at = {("vehicle/7", 0): 10, ("vehicle/7", 1): 11, ("monitor/m1", 4): 12}
        return {k: at[k] for k in keys}


def index():
    return EvidenceIndex([PV, STATE, SPAWN, dict(STATE), {"evidence": "none"}, None], Positions(), RUN)


def test_refs_and_tree_evidence_are_numbered_once_in_time_order():
    idx = index()
    assert [(r.src, r.seq) for r in idx.refs] == [("vehicle/7", 0), ("monitor/m1", 4), ("vehicle/7", 1)]
    assert idx.cite([STATE, SPAWN]) == " [E1, E3]"
    row = idx.table({}, ChainStatus(True, True, 3, None))[2]
    assert row == {"id": "E3", "run": RUN, "src": "vehicle/7", "seq": 1, "kind": "entity.state", "t": 2_000,
                   "time": row["time"], "chain_pos": 11, "used_for": []}       # verified: no "vouched"


def test_a_broken_link_vouches_for_the_events_before_it_only():
    status = ChainStatus(True, False, 3, Problem(RUN, "vehicle/7", 1, 11, "hash mismatch"))
    assert [r["vouched"] for r in index().table({}, status)] == [True, False, False]
    assert list(chain_json(status)["problem"].items()) == [("run", RUN), ("src", "vehicle/7"), ("seq", 1),
                                                           ("chain_pos", 11), ("what", "hash mismatch")]
    assert chain_text(status) == ("the run's hash chain did NOT verify: hash mismatch at chain position 11 "
                                  "(vehicle/7 #1); events from chain position 11 on are not vouched for")


def test_a_failure_that_names_no_link_vouches_for_nothing():
    status = ChainStatus(True, False, 3, None)
    assert status.to_json()["problem"] == {}
    assert [r["vouched"] for r in index().table({}, status)] == [False, False, False]
    assert chain_text(status) == "the run's hash chain did NOT verify: a link does not match"
    assert ChainStatus(False, None, None, None).to_json()["problem"] is None
