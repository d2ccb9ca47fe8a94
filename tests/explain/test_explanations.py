"""Explanations read as English built from the proofs, with the rule and the evidence cited."""
import pytest

from explain import explain_incident
from reasoner.investigation import Investigation
from sim_replay.paper import RUN, paper_run
from store import Store


@pytest.fixture(scope="module")
def explained(tmp_path_factory):
    with Store(tmp_path_factory.mktemp("x") / "s.db") as store:
        store.append(paper_run())
        inv = Investigation(store)
        out = {}
        for inc in inv.incidents(RUN):
            out[inc["vehicle"]] = explain_incident(inc, inv.rulebook)
        return out


def test_car_explanation(explained):
    text = explained["173"]
    assert text.startswith("Vehicle 173 committed a punishable violation of HC 176 (RTA 1988 s.36")
    assert "08:00:10.000 UTC" in text
    assert "because 173 has red light (fact: monitor/m1 #0, monitor.observation" in text
    assert "and it is not the case that 173 can enter the junction" in text
    assert "173 is of type ambulance is not established" in text
    assert "173 has green light is not established" in text
    assert "Liable: driver." in text


def test_ambulance_explanation(explained):
    text = explained["253"]
    assert text.startswith("Vehicle 253 committed a mitigated violation of HC 176")
    assert ("and 253 can enter the junction [HC 176 (RTA 1988 s.36; TSRGD 2016 Sch 14 Pts 1 and 4), "
            "paper.le:26]") in text
    assert "because 253 is of type ambulance (fact: vehicle/253 #0, entity.spawn" in text
    assert "it is not the case that 253 must give way to an other vehicle" in text
