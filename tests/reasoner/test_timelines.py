"""The timelines the reasoner hands explain/ (reasoner/timelines.py): typed, and the JSON the report
carries is what explain/report_data.py built from the raw events before: data/timelines_before_typed.json
was written by that code (commit 8c2183b) from the runs below. The odd run adds a signal that
names no approach (the state keys it "*"), a later approach, and monitors' speeds of car 173."""
import copy
import dataclasses
import json
from pathlib import Path

import pytest

from reasoner.timelines import ApproachPhases, Phase, SpeedSample, Timeline, timeline
from sim_replay.paper import RUN, SECOND, T0, paper_run
from store import Store

BEFORE = json.loads((Path(__file__).parent / "data" / "timelines_before_typed.json").read_text(encoding="utf-8"))


def signal(src, seq, seconds, body):
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": T0 + seconds * SECOND, "kind": "signal.state",
            "body": {"junction": "j1", **body}}


def odd(events):
    out = copy.deepcopy(events)
    out += [{"v": 1, "run": RUN, "src": "monitor/m1", "seq": 900 + n, "t": T0 + (5 + n) * SECOND,
             "kind": "monitor.observation", "body": {"vehicle": "173", "speed_mps": 8.0 - n, "facts": []}}
            for n in range(4)]
    return out + [signal("signal/j1-all", 0, 3, {"colour": "red"}), signal("signal/j1-all", 1, 8, {"colour": "amber"}),
                  signal("signal/j1-odd", 0, 9, {"colour": "green", "approach": "north"})]


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    folder = tmp_path_factory.mktemp("timelines")
    with Store(folder / "paper.db") as paper, Store(folder / "odd.db") as strange:
        paper.append(paper_run())
        assert not strange.append(odd(paper_run())).rejected
        yield {"paper": paper, "odd": strange}


@pytest.mark.parametrize("key", sorted(BEFORE))
def test_the_report_carries_the_same_json_to_the_key_order(stores, key):
    name, vehicle, seconds, junction = key.split()
    junction = None if junction == "None" else junction
    got = timeline(stores[name], RUN, T0 + int(seconds) * SECOND, vehicle, junction)
    assert json.dumps(got.to_json()) == json.dumps(BEFORE[key])


def test_the_timelines_are_values(stores):
    got = timeline(stores["odd"], RUN, T0 + 10 * SECOND, "173", "j1")
    assert isinstance(got, Timeline) and all(isinstance(s, SpeedSample) for s in got.speed)
    assert [a.approach for a in got.signals] == ["*", "west", "north"]      # the opening's, then as they came
    everyone = got.signals[0]
    assert isinstance(everyone, ApproachPhases) and everyone.phases == (Phase(T0 + 3 * SECOND, "red"),
                                                                         Phase(T0 + 8 * SECOND, "amber"))
    assert [o.speed_mps for o in got.observed_speed if o.seq >= 900] == [8.0, 7.0, 6.0, 5.0]
    with pytest.raises(dataclasses.FrozenInstanceError):
        got.junction = "j2"                                                   # type: ignore[misc]
