"""`gaps scene` and `gaps incidents --rules/--vehicle`: text for people, --json for programs,
one-line errors with exit code 2 for what names nothing, never a traceback."""
import json
import re
from pathlib import Path

import pytest

from reasoner.bundled import RULES_DIR
from sim_replay.paper import RUN, T0, paper_run
from store import Store
from tests.helpers.cli import gaps



@pytest.fixture(scope="module")
def db(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli-scene") / "gaps.db"
    events = paper_run()
    seen = next(e for e in events if e["kind"] == "vehicle.perception" and e["src"] == "vehicle/173")
    seen["body"]["facts"] = seen["body"]["facts"] + ["\x1b[31m173 juggles"]  # hostile text
    with Store(path) as store:
        store.append(events)
    return path


def test_scene_text(db):
    result = gaps("scene", "--run", RUN, "--at", "10s", db=db)
    assert result.exit_code == 0, result.output
    out = result.stdout
    assert "2024-11-21T08:00:10.000Z (+10s from the run start" in out
    assert "j1 west: red since 2024-11-21T08:00:07.000Z" in out
    assert "Vehicle 173 (car)" in out and "in control: driver" in out
    assert "at (-2.0, 0.0) m, speed 20.1 mph (9 m/s), road r1" in out  # UK unit, then the recorded one
    assert re.search(r"173 has red light +vehicle.perception vehicle/173 #2, \+9.5s", out)
    assert 'Vehicle Action: goal "173 can enter the junction", action "enter the junction"' in out
    assert "proceeds: yes" in out
    assert "Monitor Scenario of monitor/m1:" in out
    assert "\x1b" not in out and "\\x1b[31m173 juggles" in out       # shown escaped, never obeyed
    assert "lawful" not in out


def test_scene_one_vehicle_is_judged(db):
    result = gaps("scene", "--run", RUN, "--at", "2024-11-21T08:00:40.5Z", "--vehicle", "253", db=db)
    assert result.exit_code == 0, result.output
    assert "Vehicle 173" not in result.stdout
    assert "lawful: yes (paper.le, recorded" in result.stdout


def test_scene_json(db):
    result = gaps("scene", "--run", RUN, "--at", str(T0 + 10 * 10**9), "--vehicle", "173", "--json", db=db)
    assert result.exit_code == 0, result.output
    sc = json.loads(result.stdout)
    assert sc["t"] == T0 + 10 * 10**9 and sc["offset"] == "+10s"
    (car,) = sc["vehicles"]
    assert car["control"]["in_control"] == "driver"
    assert car["validator_scenario"]["lawful"] is False
    assert {"fact": "173 has red light", "evidence": {"run": RUN, "src": "vehicle/173", "seq": 2,
                                                      "t": T0 + 9_500_000_000, "kind": "vehicle.perception"}} \
        in car["vehicle_scenario"]


def test_scene_before_the_run_start_is_empty_and_says_so(db):
    result = gaps("scene", "--run", RUN, "--at", "-3s", db=db)
    assert result.exit_code == 0
    assert "nothing was recorded yet" in result.stdout and "No vehicle present" in result.stdout


@pytest.mark.parametrize("args, says", [
    (("--run", RUN, "--at", "12.5"), "needs a unit"),
    (("--run", RUN, "--at", "2024-11-21T08:00:10"), "needs a zone"),
    (("--run", RUN, "--at", "tomorrow"), "cannot read the time 'tomorrow'"),
    (("--run", "nope", "--at", "10s"), f"no run 'nope'; runs: {RUN}"),
    (("--run", RUN, "--at", "10s", "--vehicle", "999"), "vehicles present then: 173, 253"),
])
def test_scene_errors_are_one_line_and_exit_2(db, args, says):
    result = gaps("scene", *args, db=db)
    assert result.exit_code == 2
    assert says in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert result.stdout == ""


def test_scene_without_a_store(tmp_path):
    result = gaps("scene", "--run", RUN, "--at", "1s", db=tmp_path / "none.db")
    assert result.exit_code == 2 and "no event store" in result.stderr


def test_incidents_vehicle_filter_and_json_fields(db):
    result = gaps("incidents", "--run", RUN, "--vehicle", "253", "--json", db=db)
    assert result.exit_code == 0, result.output
    (found,) = json.loads(result.stdout)
    for field in ("id", "run", "t", "vehicle", "action", "rule", "verdict", "penalty", "liable", "findings",
                  "evidence"):
        assert field in found
    assert (found["vehicle"], found["verdict"]) == ("253", "mitigated")


def test_incidents_with_given_rules(db, tmp_path):
    """Given rulebooks answer the stages they define, before the run's own."""
    given = tmp_path / "my_validators.le"
    given.write_text((RULES_DIR / "validators.le").read_text(encoding="utf-8") + "\n% my copy\n", encoding="utf-8")
    result = gaps("incidents", "--run", RUN, "--rules", str(given), "--rules", str(RULES_DIR / "penalties.le"),
                  "--json", db=db)
    assert result.exit_code == 0, result.output
    by_vehicle = {i["vehicle"]: i for i in json.loads(result.stdout)}
    assert by_vehicle["173"]["rulebook"]["source"] == "given"
    assert by_vehicle["173"]["rulebook"]["name"] == str(given)
    assert by_vehicle["173"]["rulebooks"]["penalties"]["source"] == "given"
    assert by_vehicle["173"]["verdict"] == "punishable" and by_vehicle["253"]["verdict"] == "mitigated"


def test_incidents_with_a_missing_or_broken_rulebook(db, tmp_path):
    missing = gaps("incidents", "--run", RUN, "--rules", str(tmp_path / "nothing.le"), db=db)
    assert missing.exit_code == 2 and "no such rulebook file" in missing.stderr
    broken = tmp_path / "broken.le"
    broken.write_text("the templates are:\n*a vehicle* flies.\n\nthe knowledge base b includes:\n"
                      "a vehicle flies if\n    the vehicle swims.\n", encoding="utf-8")
    result = gaps("incidents", "--run", RUN, "--rules", str(broken), db=db)
    assert result.exit_code == 2 and result.stderr.startswith(f"gaps: rulebook error: {broken}:")


@pytest.mark.parametrize("args, golden", [
    (("--at", "40s"), "scene_40s.json"),
    (("--at", "10s", "--vehicle", "173"), "scene_10s_vehicle_173.json"),
])
def test_scene_json_is_what_it_was_before_the_scene_became_a_dataclass(tmp_path, args, golden):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append(paper_run())
    result = gaps("scene", "--run", RUN, *args, "--json", db=path)
    assert result.stdout == (Path(__file__).parent / "golden" / golden).read_text(encoding="utf-8")


def test_a_vehicle_inside_a_junction_has_no_road_and_none_is_printed():
    """Issue 39: `road None` on the screen for a car inside the junction (its state has no road)."""
    from explain.scene_text import vehicle_lines
    from reasoner.model import Control
    from reasoner.scene import Scene
    from reasoner.scene_parts import Reported, ValidatorShown, VehicleShown
    from store import EventRef
    state = Reported({"x": 1.75, "y": 10.92, "speed_mps": 13.41, "road": None, "junction": "j1"},
                     EventRef("r", "vehicle/124", 149, 0, "entity.state"))
    control = Control("driver", False, False, False, False, None, False, None, None, None, None)
    v = VehicleShown("124", "car", True, None, state, control, (), None, (),
                     ValidatorShown((), None, None, "spawn only"), None)
    sc = Scene(run="r", t=0, t_iso="", run_start=0, run_start_iso="", offset_ns=0, offset="+0s", events=1,
               last=None, note=None, rulebooks=(), started=None, ended=None, signals=(), monitors=(),
               vehicles=(v,), road_users=())
    line = vehicle_lines(sc, v)[1]
    assert "None" not in line and line.endswith(", in junction j1 (vehicle/124 #149, +0s)")


def test_a_signal_in_red_and_amber_is_said_in_words():
    """Issue 39: the raw token `red_amber` on the screen; TSRGD para 5(7) calls it red-and-amber."""
    from explain.scene_text import scene_lines
    from reasoner.scene import Scene
    from reasoner.scene_parts import SignalShown
    from store import EventRef
    ref = EventRef("r", "signal/j1-west", 3, 0, "signal.state")
    sc = Scene(run="r", t=0, t_iso="", run_start=0, run_start_iso="", offset_ns=0, offset="+0s", events=1,
               last=None, note=None, rulebooks=(), started=None, ended=None,
               signals=(SignalShown("j1", "west", "red_amber", ref, ref),), monitors=(), vehicles=(), road_users=())
    text = "\n".join(scene_lines(sc))
    assert "red_amber" not in text and "j1 west: red and amber since" in text
