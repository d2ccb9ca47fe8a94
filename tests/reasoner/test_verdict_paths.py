"""End to end, one test per verdict path: a small recorded run (tests/helpers/verdict_runs.py) goes into a
store, `Investigation(store).incidents(run)` judges it, and each test checks the verdict, the rule,
the penalty, who is liable and the findings that must, and must not, be there (the output contract
of DESIGN "Command line", `gaps incidents --json`, and issue 6)."""
from __future__ import annotations

import json
import random
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reasoner.bundled import bundled
from store import Store

from tests.helpers.verdict_runs import ENTER, RUN, SPEEDING, RunBuilder, car, incidents, ns
from tests.helpers.explained_cases import amber as amber_run  # cars 5 (before the line) and 6 (over it) on amber
from tests.helpers.explained_cases import av_taken_over  # 301: its driver took over before the red

VERDICTS = {"punishable", "mitigated", "dismissed"}
LIABLE = {"driver", "user-in-charge", "authorised self-driving entity", "no-user-in-charge operator", "none"}
IN_CONTROL = {"driver", "self-driving feature", "user-in-charge"}
FINDING_KINDS = {"perception fault", "decision fault", "monitor disagreement", "missing evidence", "unknown fact",
                 "contradiction", "unmeasured claim"}
REF_KEYS = {"run", "src", "seq", "t", "kind"}
FIELDS = {"id", "run", "t", "vehicle", "action", "monitor", "recorded", "rederived", "rule", "law", "verdict",
          "why", "penalty", "liable", "control", "findings", "evidence"}
PENALTY_KEYS = ("offence", "law", "fine_gbp", "points")

RTA_S36 = "Road Traffic Act 1988 section 36"
TRAFFIC_LIGHT = {"offence": "traffic light offence", "law": RTA_S36, "fine_gbp": 100, "points": 3}
STOP_SIGN = {"offence": "stop sign offence", "law": RTA_S36, "fine_gbp": 100, "points": 3}
SPEEDING_OFFENCE = {"offence": "speeding offence", "law": "Road Traffic Regulation Act 1984 section 89",
                    "fine_gbp": 100, "points": 3}
ASDE = "authorised self-driving entity"

# Findings no clean run may show (a decision fault is left out: a human driver who runs a red
# light "proceeds although not permitted", which the contract counts as one).
CLEAN = {"perception fault", "monitor disagreement", "missing evidence", "unknown fact"}


# -- helpers ----------------------------------------------------------------------------------
def judge(tmp_path: Path, events: list[dict], name: str = "s.db", **kw) -> list[dict]:
    found = incidents(tmp_path / name, events, **kw)
    check_contract(found, events)
    return found


def check_contract(found: list[dict], events: list[dict]) -> None:
    """What every incident list must be, whatever the path: the fields, their values, real
    evidence, and the order by t."""
    by_key = {(e["src"], e["seq"]): e for e in events}
    assert [i.t for i in found] == sorted(i.t for i in found), "incidents are ordered by t"
    for inc in [i.to_json() for i in found]:
        assert FIELDS <= set(inc), f"missing fields {FIELDS - set(inc)}"
        src, _, seq = inc["id"].rpartition(":")
        source = by_key[(src, int(seq))]
        assert inc["run"] == source["run"] and inc["t"] == source["t"] and inc["monitor"] == src
        assert source["kind"] == ("monitor.potential_violation" if inc["recorded"] else "monitor.observation")
        assert str(source["body"]["vehicle"]) == inc["vehicle"]
        assert isinstance(inc["recorded"], bool) and isinstance(inc["rederived"], bool)
        assert inc["recorded"] or inc["rederived"], "an incident is recorded or re-derived"
        assert inc["verdict"] in VERDICTS and inc["liable"] in LIABLE
        if inc["verdict"] == "dismissed":
            assert isinstance(inc["why"], str) and inc["why"].strip(), "a dismissal says why"
        if inc["verdict"] != "punishable":
            assert inc["penalty"] is None and inc["liable"] == "none"
        elif inc["penalty"] is not None:
            assert set(PENALTY_KEYS) <= set(inc["penalty"])
        assert inc["control"]["in_control"] in IN_CONTROL
        for ref in inc["evidence"]:
            check_ref(ref, by_key)
        for f in inc["findings"]:
            assert f["kind"] in FINDING_KINDS, f
            assert isinstance(f["detail"], str) and f["detail"]
            for ref in f["evidence"]:
                check_ref(ref, by_key)
    json.dumps([i.summary_json() for i in found])       # as `gaps incidents --json` prints it


def check_ref(ref: dict, by_key: dict) -> None:
    assert REF_KEYS <= set(ref), ref
    event = by_key.get((ref["src"], ref["seq"]))
    assert event is not None, f"evidence {ref} names no event of the run"
    assert (ref["run"], ref["t"], ref["kind"]) == (event["run"], event["t"], event["kind"]), ref


def one(found: list[dict], vehicle: str) -> dict:
    mine = [i for i in found if i.vehicle == vehicle]
    assert len(mine) == 1, f"{len(mine)} incidents of {vehicle}: {[(i.id, i.action) for i in mine]}"
    return mine[0]


def kinds(inc: dict) -> set[str]:
    return {f.kind for f in inc.findings}


def findings(inc: dict, kind: str) -> list[dict]:
    return [f for f in inc.findings if f.kind == kind]


def penalty(inc: dict) -> dict | None:
    p = inc.penalty
    return None if p is None else {k: getattr(p, k) for k in PENALTY_KEYS}


def refs(items) -> set[tuple[str, int]]:
    return {r.key for r in items}


def key(event: dict) -> tuple[str, int]:
    return (event["src"], event["seq"])


def assert_findings(inc: dict, must: set[str] = frozenset(), must_not: set[str] = CLEAN) -> None:
    got = kinds(inc)
    assert must <= got, f"{inc.vehicle}: expected findings {must - got}, got {inc.findings}"
    unexpected = (must_not - must) & got
    assert not unexpected, f"{inc.vehicle}: unexpected findings {[f for f in inc.findings if f.kind in unexpected]}"


# -- the runs ---------------------------------------------------------------------------------
def paper_scenarios(run: RunBuilder) -> dict:
    """Section 7.2: car 173 and ambulance 253 (on an emergency call) enter j1 on red."""
    run.spawn("173", "car")
    run.spawn("253", "ambulance", emergency=True)
    run.lights(10, "red")
    c173 = run.crossing("173", 10, car("173") + ["173 has red light"],
                        ["173 has red light", "173 crossed the stop line on red light"])
    run.lights(40, "red")
    c253 = run.crossing("253", 40, ["253 is of type ambulance", "253 has red light", "253 is on an emergency call"],
                        ["253 has red light", "253 crossed the stop line on red light"])
    return {"173": c173, "253": c253}


def assert_punishable(inc: dict, rule: str, pen: dict, law_part: str, liable: str = "driver") -> None:
    assert inc.verdict == "punishable", (inc.verdict, inc.why, inc.findings)
    assert inc.rule == rule
    assert isinstance(inc.law, str) and law_part in inc.law, inc.law
    assert penalty(inc) == pen
    assert inc.liable == liable


def assert_mitigated(inc: dict, rule: str) -> None:
    assert inc.verdict == "mitigated", (inc.verdict, inc.why, inc.findings)
    assert inc.rule == rule
    assert inc.penalty is None and inc.liable == "none"


# 1 -------------------------------------------------------------------------------------------
def test_paper_car_173_punishable_and_ambulance_253_mitigated(tmp_path):
    run = RunBuilder()
    c = paper_scenarios(run)
    found = judge(tmp_path, run.finish())
    assert len(found) == 2

    i173 = one(found, "173")
    assert_punishable(i173, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert i173.id == f"monitor/m1:{c['173']['pv']['seq']}" and i173.t == ns(10)
    assert (i173.action, i173.monitor, i173.run) == (ENTER, "monitor/m1", RUN)
    assert i173.recorded is True and i173.rederived is True
    assert i173.control.in_control == "driver"
    assert_findings(i173)
    assert refs(i173.evidence) >= {key(c["173"][k]) for k in ("pv", "decision", "perception", "observation")}

    i253 = one(found, "253")
    assert_mitigated(i253, "HC 176")
    assert i253.id == f"monitor/m1:{c['253']['pv']['seq']}"
    assert i253.recorded is True and i253.rederived is True
    assert i253.control.in_control == "driver"
    # its own rulebook lets an ambulance on call enter on red: its decision is no fault either
    assert_findings(i253, must_not=CLEAN | {"decision fault"})
    assert found.index(i173) < found.index(i253)


def test_paper_demo_run_verdicts(tmp_path):
    from sim_replay.paper import RUN as PAPER_RUN
    from sim_replay.paper import paper_run

    found = judge(tmp_path, paper_run(), run=PAPER_RUN)
    i173, i253 = one(found, "173"), one(found, "253")
    assert (i173.verdict, i173.rule, i173.liable) == ("punishable", "HC 176", "driver")
    assert (i253.verdict, i253.penalty, i253.liable) == ("mitigated", None, "none")


# 2 -------------------------------------------------------------------------------------------
def test_ambulance_off_call_on_red_is_punishable(tmp_path):
    run = RunBuilder()
    run.spawn("254", "ambulance", emergency=False)
    run.lights(10, "red")
    run.crossing("254", 10, ["254 is of type ambulance", "254 has red light"],
                 ["254 has red light", "254 crossed the stop line on red light"])
    inc = one(judge(tmp_path, run.finish()), "254")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(inc)


# 3 -------------------------------------------------------------------------------------------
def test_ambulance_on_call_forcing_a_pedestrian_to_stop_is_punishable(tmp_path):
    run = RunBuilder()
    run.spawn("255", "ambulance", emergency=True)
    run.lights(10, "red")
    c = run.crossing("255", 10, ["255 is of type ambulance", "255 has red light", "255 is on an emergency call",
                                 "p1 is of type pedestrian", "255 would force p1 to change speed or course"],
                     ["255 has red light", "255 crossed the stop line on red light"])
    assert c["decision"]["body"]["permitted"] is False       # its own rulebook says so too
    inc = one(judge(tmp_path, run.finish()), "255")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(inc)


def test_ambulance_on_call_with_nobody_forced_is_mitigated(tmp_path):
    """The control of test 3: the same ambulance without the pedestrian is mitigated."""
    run = RunBuilder()
    run.spawn("255", "ambulance", emergency=True)
    run.lights(10, "red")
    run.crossing("255", 10, ["255 is of type ambulance", "255 has red light", "255 is on an emergency call"],
                 ["255 has red light", "255 crossed the stop line on red light"])
    assert_mitigated(one(judge(tmp_path, run.finish()), "255"), "HC 176")


# 4 -------------------------------------------------------------------------------------------
def test_crossing_on_amber_is_punishable_and_amber_after_crossing_is_no_violation(tmp_path):
    """HC 175: car 5 crossed the stop line on amber, not too close to stop: punishable. Car 6 was
    over the line on green when the amber appeared ("you may go on only if the AMBER appears after
    you have crossed the stop line"): the monitor's own observation shows it crossed on green, so the
    potential violation recorded against it is no act the law forbids, and is dismissed. (Read as
    a snapshot, "has crossed the stop line" with amber showing, it used to be mitigated; issue 12.)"""
    run = RunBuilder()
    amber_run(run)
    found = judge(tmp_path, run.finish())
    assert len(found) == 2
    i5 = one(found, "5")
    assert_punishable(i5, "HC 175", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(i5)
    i6 = one(found, "6")
    assert (i6.verdict, i6.recorded, i6.rederived) == ("dismissed", True, False), (i6.verdict, i6.why)
    assert i6.penalty is None and i6.liable == "none"
    assert_findings(i6, must={"monitor disagreement"}, must_not=CLEAN | {"decision fault"})


def test_amber_too_close_to_stop_is_mitigated(tmp_path):
    run = RunBuilder()
    run.spawn("7", "car")
    run.lights(10, "amber")
    run.crossing("7", 10, car("7") + ["7 has amber light", "7 is too close to the stop line to stop safely"],
                 ["7 has amber light", "7 crossed the stop line on amber light"])
    inc = one(judge(tmp_path, run.finish()), "7")
    assert_mitigated(inc, "HC 175")
    assert_findings(inc, must_not=CLEAN | {"decision fault"})


# 5 -------------------------------------------------------------------------------------------
def test_stop_sign_rolled_through_is_punishable(tmp_path):
    run = RunBuilder()
    run.spawn("8", "car")
    c = run.crossing("8", 10, car("8") + ["8 has a stop sign", "8 has crossed the stop line"],
                     ["8 has a stop sign", "8 has crossed the stop line"], junction="j2")
    inc = one(judge(tmp_path, run.finish()), "8")
    assert inc.monitor == "monitor/m2" and inc.id == f"monitor/m2:{c['pv']['seq']}"
    assert_punishable(inc, "HC 171", STOP_SIGN, "TSRGD 2016 Sch 9")
    assert_findings(inc)


# 6 -------------------------------------------------------------------------------------------
def test_speeding_is_punishable(tmp_path):
    run = RunBuilder()
    run.spawn("28", "car")
    run.lights(10, "green")
    speed = ["28 has speed of 38", "the speed limit is 30"]
    c = run.crossing("28", 10, car("28") + ["28 has green light"] + speed, ["28 has green light"] + speed,
                     action=SPEEDING, goal=ENTER, speed_mps=17.0)
    assert c["decision"]["body"]["permitted"] is True        # entering on green is lawful
    inc = one(judge(tmp_path, run.finish()), "28")
    assert inc.action == SPEEDING
    assert_punishable(inc, "HC 124", SPEEDING_OFFENCE, "Road Traffic Regulation Act 1984 s.89")
    assert_findings(inc, must_not=CLEAN | {"decision fault"})


# 7 -------------------------------------------------------------------------------------------
def av_saw_green(run: RunBuilder, v: str = "300", at: float = 30) -> dict:
    run.spawn(v, "car", driver="autonomous", automation_level=4)
    run.ads(v, "activated", at - 20)
    run.lights(at, "red")
    return run.crossing(v, at, car(v) + [f"{v} is driving itself", f"{v} has green light"],
                        [f"{v} has red light", f"{v} crossed the stop line on red light"])


def test_self_driving_car_that_saw_green_on_red_is_the_asdes(tmp_path):
    run = RunBuilder()
    c = av_saw_green(run)
    assert c["decision"]["body"]["permitted"] is True        # right on what it saw
    inc = one(judge(tmp_path, run.finish()), "300")
    # judged on what the monitor observed: red; the ASDE faces regulatory sanctions, not a driver's
    # fixed penalty and points (Automated Vehicles Act 2024; liability.le)
    assert_punishable(inc, "HC 176", {**TRAFFIC_LIGHT, "fine_gbp": None, "points": 0}, "TSRGD 2016 Sch 14",
                      liable=ASDE)
    assert (inc.penalty.fine_gbp_by_law, inc.penalty.points_by_law) == (100, 3)
    assert ASDE in inc.penalty.regulatory_sanctions and inc.liability.fixed_penalty == ()
    assert inc.control.in_control == "self-driving feature"
    assert_findings(inc, must={"perception fault"}, must_not=CLEAN | {"decision fault"})
    fault = findings(inc, "perception fault")[0]
    assert refs(fault.evidence) >= {key(c["perception"]), key(c["observation"])}


# 8 -------------------------------------------------------------------------------------------
def test_self_driving_car_taken_over_by_its_driver_before_the_red_is_the_drivers(tmp_path):
    run = RunBuilder()
    av_taken_over(run)
    inc = one(judge(tmp_path, run.finish()), "301")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14", liable="driver")
    assert inc.control.in_control == "driver"
    assert_findings(inc)


def test_self_driving_car_still_engaged_is_not_the_drivers(tmp_path):
    """The control of test 8: the same run without the override is the ASDE's."""
    run = RunBuilder()
    run.spawn("301", "car", driver="autonomous", automation_level=4)
    run.ads("301", "activated", 0.5)
    run.lights(30, "red")
    run.crossing("301", 30, car("301") + ["301 is driving itself", "301 has red light"],
                 ["301 has red light", "301 crossed the stop line on red light"])
    inc = one(judge(tmp_path, run.finish()), "301")
    assert inc.verdict == "punishable" and inc.liable == ASDE
    assert inc.control.in_control == "self-driving feature"
    assert (penalty(inc)["fine_gbp"], penalty(inc)["points"]) == (None, 0)


# 9 -------------------------------------------------------------------------------------------
_MIXED: list[dict] | None = None


def mixed_run() -> list[dict]:
    """Several paths in one run (tens of events): red, emergency, amber, a perception fault, an
    unrecorded potential violation, speeding."""
    global _MIXED
    if _MIXED is None:
        run = RunBuilder()
        paper_scenarios(run)                       # t 10 and 40
        run.spawn("5", "car")
        run.lights(60, "amber")
        run.crossing("5", 60, car("5") + ["5 has amber light"],
                     ["5 has amber light", "5 crossed the stop line on amber light"])
        av_saw_green(run, "300", 80)
        run.spawn("41", "car")
        run.lights(100, "red")
        run.crossing("41", 100, car("41") + ["41 has red light"],
                     ["41 has red light", "41 is in the junction"], record=False,
                     observations=2)
        run.spawn("28", "car", at=1)
        run.lights(115, "green")
        speed = ["28 has speed of 38", "the speed limit is 30"]
        run.crossing("28", 115, car("28") + ["28 has green light"] + speed, ["28 has green light"] + speed,
                     action=SPEEDING, goal=ENTER, speed_mps=17.0)
        _MIXED = run.finish(130)
    return [dict(e) for e in _MIXED]


_REFERENCE: list[dict] | None = None


def reference() -> list[dict]:
    global _REFERENCE
    if _REFERENCE is None:
        with tempfile.TemporaryDirectory() as d:
            _REFERENCE = incidents(Path(d) / "ref.db", mixed_run())
            check_contract(_REFERENCE, mixed_run())
    return _REFERENCE


def test_mixed_run_has_every_path(tmp_path):
    found = reference()
    assert [i.vehicle for i in found] == ["173", "253", "5", "300", "41", "28"]
    assert [i.verdict for i in found] == ["punishable", "mitigated", "punishable", "punishable",
                                            "punishable", "punishable"]
    assert [i.liable for i in found] == ["driver", "none", "driver", ASDE, "driver", "driver"]


@pytest.mark.parametrize("order", ["reversed", "shuffled", "batches of 1", "batches of 7", "all at once"])
def test_out_of_order_arrival_gives_the_same_incidents(tmp_path, order):
    events = mixed_run()
    batches = None
    if order == "reversed":
        events.reverse()
    elif order == "shuffled":
        random.Random(6).shuffle(events)
    elif order.startswith("batches"):
        random.Random(len(order)).shuffle(events)
        batches = int(order.split()[-1])
    assert incidents(tmp_path / "s.db", events, batches=batches) == reference()


@settings(max_examples=8, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), batch=st.sampled_from([1, 3, 7, None]))
def test_any_arrival_order_gives_the_same_incidents(data, batch):
    events = mixed_run()
    shuffled = data.draw(st.permutations(events), label="arrival order")
    with tempfile.TemporaryDirectory() as d:
        assert incidents(Path(d) / "s.db", shuffled, batches=batch) == reference()


# 10 ------------------------------------------------------------------------------------------
def hostile_strings(sentinel: Path) -> list[str]:
    return [
        "173 has red light). halt. (",
        f"X :- shell('touch {sentinel}')",
        "'$not'(x)",
        f":- initialization(shell('touch {sentinel}')).",
        "x" * 10_240,
        "\x00\x07\x1b[31m\u202e\u200b\x7f bell",
        " ",            # the nearest to an empty string the event schema lets through
    ]


def hostile_run(extra_perceived: list[str], extra_observed: list[str]) -> tuple[list[dict], dict]:
    run = RunBuilder()
    run.spawn("173", "car")
    run.lights(10, "red")
    c = run.crossing("173", 10, car("173") + ["173 has red light"] + extra_perceived,
                     ["173 has red light", "173 crossed the stop line on red light"] + extra_observed)
    return run.finish(), c


def test_hostile_fact_strings_are_unknown_facts_and_change_nothing(tmp_path):
    sentinel = tmp_path / "pwned"
    hostile = hostile_strings(sentinel)
    parseable_hostile = f"173 is of type shell('touch {tmp_path / 'pwned2'}')"   # fits a template: data only
    clean = one(judge(tmp_path, hostile_run([], [])[0], "clean.db"), "173")
    events, c = hostile_run(hostile + [parseable_hostile], hostile)
    inc = one(judge(tmp_path, events, "hostile.db"), "173")

    assert not sentinel.exists() and not (tmp_path / "pwned2").exists(), "a fact string was run as code"
    for field in ("verdict", "rule", "law", "penalty", "liable", "control", "recorded", "rederived"):
        assert getattr(inc, field) == getattr(clean, field), field
    unknown = findings(inc, "unknown fact")
    reported = [s for s in hostile if s.strip()]
    for where in (c["perception"], c["observation"]):
        about = [f for f in unknown if key(where) in refs(f.evidence)]
        assert len(about) >= len(reported), (where["kind"], [f.detail[:80] for f in about])
    readable = [s for s in reported if s.isascii() and s.isprintable() and len(s) < 100]
    for s in readable:
        assert any(s in f.detail or s == f.fact for f in unknown), f"{s!r} is not reported"
    assert kinds(inc) - {"unknown fact"} == kinds(clean)
    assert not findings(clean, "unknown fact")


def test_an_empty_fact_string_never_reaches_the_reasoner(tmp_path):
    """The schema refuses an empty sentence: the event is quarantined at the door."""
    events, c = hostile_run(["", "173 has red light"], [])
    with Store(tmp_path / "s.db") as store:
        report = store.append(events)
        assert len(report.rejected) == 1 and store.quarantine_count() == 1


# 11 ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("says, proceeds", [(True, True), (False, True)],
                         ids=["permitted on red", "proceeds although not permitted"])
def test_decision_fault(tmp_path, says, proceeds):
    run = RunBuilder()
    run.spawn("173", "car")
    run.lights(10, "red")
    c = run.crossing("173", 10, car("173") + ["173 has red light"],
                     ["173 has red light", "173 crossed the stop line on red light"], says=says,
                     proceeds=proceeds)
    inc = one(judge(tmp_path, run.finish()), "173")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(inc, must={"decision fault"})
    assert key(c["decision"]) in refs(findings(inc, "decision fault")[0].evidence)


def test_no_decision_fault_when_the_decision_follows_the_rulebook(tmp_path):
    """The control of test 11: an ambulance on call that its rulebook lets in, and goes in."""
    run = RunBuilder()
    run.spawn("253", "ambulance", emergency=True)
    run.lights(10, "red")
    run.crossing("253", 10, ["253 is of type ambulance", "253 has red light", "253 is on an emergency call"],
                 ["253 has red light", "253 crossed the stop line on red light"], says=True)
    inc = one(judge(tmp_path, run.finish()), "253")
    assert_findings(inc, must_not=CLEAN | {"decision fault"})


# 12 ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("dropped", ["vehicle state at the incident", "vehicle approach", "monitor's earlier observation"])
def test_missing_evidence_around_the_incident(tmp_path, dropped):
    run = RunBuilder()
    run.spawn("173", "car")
    run.lights(10, "red")
    c = run.crossing("173", 10, car("173") + ["173 has red light"],
                     ["173 has red light", "173 crossed the stop line on red light"], observations=2)
    events = run.finish()
    gone = {"vehicle state at the incident": c["state"], "vehicle approach": c["approach"],
            "monitor's earlier observation": c["observations"][0]}[dropped]
    clean = one(judge(tmp_path, events, "clean.db"), "173")
    assert_findings(clean)
    inc = one(judge(tmp_path, [e for e in events if e is not gone], "gap.db"), "173")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(inc, must={"missing evidence"}, must_not=CLEAN - {"missing evidence"})
    missing = findings(inc, "missing evidence")
    assert any(gone["src"] in f.detail or gone["src"] in {r.src for r in f.evidence} for f in missing), \
        missing


# 13 ------------------------------------------------------------------------------------------
def test_red_light_runner_the_monitor_did_not_record(tmp_path):
    run = RunBuilder()
    run.spawn("41", "car")
    run.lights(10, "red")
    c = run.crossing("41", 10, car("41") + ["41 has red light"], ["41 has red light", "41 is in the junction"],
                     record=False, observations=2)
    inc = one(judge(tmp_path, run.finish()), "41")
    first = c["observations"][0]
    assert inc.id == f"monitor/m1:{first['seq']}" and inc.t == first["t"]
    assert inc.recorded is False and inc.rederived is True
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert_findings(inc, must={"monitor disagreement"})
    assert refs(inc.evidence) & {key(o) for o in c["observations"]}


def test_recorded_violation_the_observation_does_not_support_is_dismissed(tmp_path):
    run = RunBuilder()
    run.spawn("42", "car")
    run.lights(10, "red")
    c = run.crossing("42", 10, car("42") + ["42 has red light"], ["42 has red light", "42 is stopped"],
                     proceeds=False)
    assert c["decision"]["body"]["permitted"] is False
    inc = one(judge(tmp_path, run.finish()), "42")
    assert inc.id == f"monitor/m1:{c['pv']['seq']}"
    assert inc.recorded is True and inc.rederived is False
    assert inc.verdict == "dismissed" and inc.why
    assert inc.penalty is None and inc.liable == "none"
    assert_findings(inc, must={"monitor disagreement"}, must_not=CLEAN | {"decision fault"})
    assert key(c["pv"]) in refs(findings(inc, "monitor disagreement")[0].evidence)


# 14 ------------------------------------------------------------------------------------------
AMBER_ALWAYS = """
% amber is always allowed (a rulebook under test, not the law)
a vehicle may go on at the amber light if
    the vehicle is of type a type.
"""


def lenient_validators() -> str:
    text = bundled("validators.le")
    marker = "% end of restatement\n"
    assert marker in text
    return text.replace(marker, marker + AMBER_ALWAYS, 1)


@pytest.mark.parametrize("given_as", ["path", "text"])
def test_another_rulebook_changes_the_amber_verdict(tmp_path, given_as):
    run = RunBuilder()
    amber_run(run)
    events = run.finish()
    default = one(judge(tmp_path, events, "default.db"), "5")
    assert default.verdict == "punishable"

    lenient = lenient_validators()
    as_given = [lenient]
    if given_as == "path":
        (tmp_path / "validators.le").write_text(lenient, encoding="utf-8")
        as_given = [str(tmp_path / "validators.le")]
    found = judge(tmp_path, events, "lenient.db", rules=as_given)
    assert_mitigated(one(found, "5"), "HC 175")
    assert one(found, "6").verdict == "dismissed"     # no act to judge: a validator rulebook cannot change that

    same = [bundled("validators.le")]
    assert one(judge(tmp_path, events, "same.db", rules=same), "5").verdict == "punishable"


# 15: a camera that knows only DESIGN's core vocabulary (issue 12) ------------------------------
def camera_run(vehicle: str, type: str, observed: list[str], *, emergency: bool = False,
               record: bool = True, proceeds: bool = True) -> list[dict]:
    """A vehicle that records nothing of its own (a human driver without a recorder), seen by a
    roadside camera that writes core sentences only: judged on the monitor scenario. Its own
    positions say where it was: through the junction at 9 m/s, or (proceeds=False) braking to
    a stop 15 m before the centre, outside the junction."""
    run = RunBuilder()
    run.spawn(vehicle, type, emergency=emergency)
    run.lights(10, "red")
    run.state(vehicle, 9.0, -20.0, 9.0 if proceeds else 5.0)
    run.observe(vehicle, 10.0, observed)
    if record:
        run.potential_violation(vehicle, 10.0, ENTER, observed)
    if proceeds:
        run.state(vehicle, 11.0, 7.0, 9.0, "j1")
    else:
        run.state(vehicle, 11.0, -15.0, 0.0)
    return run.finish()


def test_a_car_braking_to_a_stop_at_red_has_done_nothing(tmp_path):
    """TSRGD para 5(3): the offence is proceeding beyond the stop line. A car with a red light,
    still moving but not over the line, is no potential violation; one a monitor recorded anyway
    is dismissed."""
    braking = ["1 is of type car", "1 has red light", "1 has speed of 12", "the speed limit is 30"]
    assert judge(tmp_path, camera_run("1", "car", braking, record=False, proceeds=False), "unrecorded.db") == []
    (inc,) = judge(tmp_path, camera_run("1", "car", braking, proceeds=False), "recorded.db")
    assert (inc.verdict, inc.rederived, inc.penalty) == ("dismissed", False, None)


def test_a_car_over_the_line_on_green_clearing_on_red_has_done_nothing(tmp_path):
    """HC 176 / para 5(3): it crossed on green; red showing as it clears the junction is no act."""
    clearing = ["2 is of type car", "2 has red light", "2 is in the junction", "2 crossed the stop line on green light"]
    assert judge(tmp_path, camera_run("2", "car", clearing, record=False)) == []


def test_a_red_light_runner_seen_by_a_camera_in_core_sentences_is_punishable(tmp_path):
    """The snapshot: red showing and the car in the junction, no crossing time recorded."""
    (inc,) = judge(tmp_path, camera_run("3", "car", ["3 is of type car", "3 has red light", "3 is in the junction"]))
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")
    assert inc.judged_on == "monitor scenario"


@pytest.mark.parametrize("road_user, verdict", [("pedestrian", "punishable"), ("cyclist", "mitigated"),
                                                ("car", "mitigated")])
def test_an_ambulance_on_call_with_a_road_user_approaching(tmp_path, road_user, verdict):
    """TSRGD para 5(5): a pedestrian approaching an ambulance that proceeds on red is likely to be
    endangered (punishable); a car approaching is not, by that alone, made to change speed or
    course (mitigated: nothing shows it braked), nor is a cyclist, the driver of a vehicle whose
    approach is traffic's (HC 172): it is endangered only in or entering the ambulance's path, which
    nothing here measures (issue 35; this expected punishable before)."""
    observed = ["4 is of type ambulance", "4 is on an emergency call", "4 crossed the stop line on red light",
                f"u1 is of type {road_user}", "u1 is approaching 4"]
    (inc,) = judge(tmp_path, camera_run("4", "ambulance", observed, emergency=True))
    assert inc.verdict == verdict, (inc.verdict, inc.why)
    assert inc.rule == "HC 176"


def test_a_pedestrian_only_the_camera_saw_counts_against_an_ambulance_that_recorded_its_own_view(tmp_path):
    """TSRGD para 5(5) again, on the vehicle-scenario path: the ambulance records its perception
    (its call, its red light, nobody about) and the camera states "p1 is approaching 8" and "p1
    is of type pedestrian". What the monitor saw of a road user the vehicle perceived nothing of
    joins the Validator Scenario, so the endangered pedestrian makes it punishable."""
    run = RunBuilder()
    run.spawn("8", "ambulance", emergency=True)
    run.lights(10, "red")
    own = ["8 is of type ambulance", "8 is on an emergency call", "8 has red light"]
    seen = ["8 has red light", "8 crossed the stop line on red light", "p1 is approaching 8",
            "p1 is of type pedestrian"]
    run.crossing("8", 10, own, seen)
    inc = one(judge(tmp_path, run.finish()), "8")
    assert inc.judged_on == "vehicle scenario"
    assert "p1 is of type pedestrian" in [s for s, _ in inc.scenarios.validator]
    assert inc.verdict == "punishable" and inc.rule == "HC 176", (inc.verdict, inc.why)


def test_an_unmarked_police_car_on_a_call_is_exempt_and_an_ambulance_off_call_is_not(tmp_path):
    """TSRGD para 5(6): the exemption follows the purpose (an emergency call), not the type."""
    unmarked = ["5 is of type car", "5 is on an emergency call", "5 crossed the stop line on red light"]
    (inc,) = judge(tmp_path, camera_run("5", "car", unmarked, emergency=True), "unmarked.db")
    assert_mitigated(inc, "HC 176")
    returning = ["6 is of type ambulance", "6 crossed the stop line on red light"]
    (inc,) = judge(tmp_path, camera_run("6", "ambulance", returning), "returning.db")
    assert_punishable(inc, "HC 176", TRAFFIC_LIGHT, "TSRGD 2016 Sch 14")


def test_speeding_on_a_call_is_exempt_and_off_a_call_is_not(tmp_path):
    """RTRA 1984 s.87: the limit does not apply to a vehicle on an emergency call."""
    for name, emergency in (("on", True), ("off", False)):
        run = RunBuilder()
        run.spawn("7", "ambulance", emergency=emergency)
        speed = ["7 is of type ambulance", "7 has speed of 50", "the speed limit is 30"]
        run.observe("7", 10.0, speed)
        run.potential_violation("7", 10.0, SPEEDING, speed)
        (inc,) = judge(tmp_path, run.finish(), f"{name}.db")
        assert inc.verdict == ("mitigated" if emergency else "punishable"), (name, inc.why)
        assert inc.rule == "HC 124"


def test_a_stop_sign_run_with_a_worn_line_and_a_lawful_stop(tmp_path):
    """HC 171, TSRGD Sch 9 Pt 7 para 1: with the line not clearly visible, entering the major road
    without having stopped before it is punishable; a vehicle that stopped at the line and went
    on is lawful."""
    run = RunBuilder()
    run.spawn("8", "car")
    worn = ["8 is of type car", "8 has a stop sign", "the stop line is not clearly visible for 8",
            "8 is in the junction"]
    run.observe("8", 10.0, worn, "m2")
    run.potential_violation("8", 10.0, ENTER, worn, "m2")
    run.spawn("9", "car")
    lawful = ["9 is of type car", "9 has a stop sign", "9 has stopped at the stop line", "9 has crossed the stop line"]
    run.observe("9", 40.0, lawful, "m2")
    run.potential_violation("9", 40.0, ENTER, lawful, "m2")
    found = judge(tmp_path, run.finish())
    assert_punishable(one(found, "8"), "HC 171", STOP_SIGN, "TSRGD 2016 Sch 9")
    assert one(found, "9").verdict == "dismissed"          # no act: it stopped at the line


# rulebooks -----------------------------------------------------------------------------------
def test_a_run_without_rulebooks_is_judged_with_the_current_ones_and_says_so(tmp_path):
    recorded, bare = RunBuilder(), RunBuilder(books=None)
    paper_scenarios(recorded)
    paper_scenarios(bare)
    with_books = judge(tmp_path, recorded.finish(), "recorded.db")
    without = judge(tmp_path, bare.finish(), "bare.db")
    assert '"current"' in json.dumps(without[0].to_json()["rulebooks"])
    assert '"current"' not in json.dumps(with_books[0].to_json()["rulebooks"])
    for a, b in zip(with_books, without):
        assert (a.verdict, a.rule, a.penalty, a.liable) == (b.verdict, b.rule, b.penalty, b.liable)


def test_a_stated_fact_the_measurements_contradict_is_a_finding_not_an_override(tmp_path):
    """DESIGN "Reasoning": a stated fact and a derived one that disagree is a finding. The camera
    states 50 mph in a 30 limit; the car's own positions say 9 m/s (20 mph). Nothing is silently
    replaced (the measured speed is held back from the scenario), the contradiction, with the
    camera's event and the measurements, is a finding, and since the verdict turns on it
    (DESIGN "Weighing"), neither side decides: not proven, dismissed under HC 124."""
    run = RunBuilder()
    run.spawn("7", "car")
    run.state("7", 9.0, -60.0, 9.0)
    said = ["7 is of type car", "7 has speed of 50", "the speed limit is 30"]
    obs = run.observe("7", 10.0, said)
    run.potential_violation("7", 10.0, SPEEDING, said)
    run.state("7", 11.0, -42.0, 9.0)
    inc = one(judge(tmp_path, run.finish()), "7")
    assert inc.verdict == "dismissed" and inc.rule == "HC 124" and inc.why.startswith("not proven:"), inc.why
    (c,) = findings(inc, "contradiction")
    assert '"7 has speed of 50" was stated' in c.detail and "20.1 mph" in c.detail
    assert (obs["src"], obs["seq"]) in {(r.src, r.seq) for r in c.evidence}
    assert {r.kind for r in c.evidence} >= {"monitor.observation", "entity.state"}
    assert "7 has speed of 20" not in [s for s, _ in inc.scenarios.monitor]     # the measured speed is held back


def test_a_main_road_car_the_vehicle_never_perceived_still_counts_as_on_the_main_road(tmp_path):
    """HC 172: 212, driving itself, perceived only its sign; the monitor saw 107 approaching on the
    main road. The Validator Scenario is the vehicle's view corrected by what the monitor
    witnessed: 212 holds no view of 107 at all, so the monitor's "107 is on the main road" joins it
    beside "107 is approaching 212" (found by the simulation's ground truth, where it was lost, so
    that a car forcing 107 to brake, measured, was judged mitigated)."""
    run = RunBuilder()
    run.spawn("212", "car", driver="autonomous", automation_level=4)
    run.spawn("107", "car")                 # a road user the record knows, as in a simulated run
    run.ads("212", "activated", 1.0)
    run.crossing("212", 10, ["212 is of type car", "212 is driving itself", "212 has a give way sign"],
                 ["212 is of type car", "212 has a give way sign", "212 has crossed the stop line", "212 is in the junction",
                  "107 is of type car", "107 is approaching 212", "107 is on the main road"])
    inc = one(judge(tmp_path, run.finish()), "212")
    validator = [text for text, _ in inc.scenarios.validator]
    assert "107 is on the main road" in validator and "107 is approaching 212" in validator, validator
