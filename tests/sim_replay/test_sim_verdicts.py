"""End to end: a seeded simulated run, stored, investigated, and the verdicts compared with the ground truth.

The run (60 road users, 150 s on the paper's map, habits and the misread-light fault raised so that
acts happen) is appended to a Store; reasoner.investigation judges it; tests/helpers/sim_truth_table turns each act
of the ground truth into the verdict the law should give and lines them up. Every disagreement is
printed (pytest -s). The ones in the table's KNOWN are known and explained (the note of the
sim-agents branch gives the evidence for each); any other fails the test. They are findings about
the reasoner and its rulebooks, not tuned away in the simulation.
"""
from __future__ import annotations

import pytest

from reasoner.investigation import Investigation
from sim_replay.sim_config import Behaviour, FaultRates, SimConfig
from sim_replay.sim_events import T0
from sim_replay.simulation import Simulation
from store import Store

from tests.helpers.sim_truth_table import compare

RUN = SimConfig(run="sim-e2e", vehicles=60, duration_s=150.0, seed=7, emergency_share=0.15, pedestrians=8,
                av_share=0.4, behaviour=Behaviour(red_runner=0.3, amber_runner=0.4, stop_roller=0.4, no_give_way=0.4,
                                                  speeder=0.2),
                faults=FaultRates(misperceived_light=0.5))

@pytest.fixture(scope="module")
def judged(tmp_path_factory):
    sim = Simulation(RUN)
    events = list(sim.events())
    store = Store(tmp_path_factory.mktemp("sim") / "gaps.db")
    report = store.append(events)
    assert report.stored == len(events) and not report.rejected
    incidents = Investigation(store).incidents(RUN.run)
    return sim, compare(sim.truth.to_json(), incidents, T0)


def test_the_run_has_the_acts_the_table_is_about(judged):
    sim, lines = judged
    rows = {line.row.name for line in lines if line.row is not None}
    assert rows >= {"crossed on red, no call", "crossed on red on a call, nobody endangered",
                    "crossed on amber, too close to stop", "crossed on amber, could have stopped",
                    "over a Stop line without stopping", "over the limit", "over the limit on a call"}
    assert any(f.kind == "misperceived_light" for f in sim.truth.faults)


def test_incidents_agree_with_the_ground_truth_but_for_known_findings(judged):
    _, lines = judged
    unexplained = []
    for line in lines:
        if line.agrees:
            continue
        print("DISAGREES", line.describe(), "|", line.known or "UNEXPLAINED")
        if line.known is None:
            unexplained.append(line.describe())
    agreed = [line for line in lines if line.agrees and line.incidents]
    assert len(agreed) >= 10
    assert unexplained == []


def test_a_red_light_crossed_after_misreading_it_is_the_asdes(judged):
    _, lines = judged
    faulted = [line for line in lines if line.act and (line.act["fault"] or "").startswith("misperceived_light: saw green")
               and line.act["light"] == "red" and line.incidents]
    assert faulted
    for line in faulted:
        (inc,) = line.incidents
        assert inc.verdict == "punishable" and any(f.kind == "perception fault" for f in inc.findings)
        assert inc.liable == "authorised self-driving entity"
