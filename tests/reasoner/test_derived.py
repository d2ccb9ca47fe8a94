"""Derived facts (reasoner/derived.py): what they cite, that they never override a stated fact,
and that every sentence they write is one the rulebooks read."""
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reasoner import derived, history, stopping
from reasoner import vocabulary as vocab
from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.le.sentences import parse_fact
from reasoner.model import Margin
from reasoner.history import MPH_PER_MPS
from reasoner.history import LINE_EPS_M
from store import EventRef
from tests.helpers.foreign import SECOND, T0, Foreign, Motion, crossroads, irregular, ns, rate

STATED = EventRef("foreign-1", "monitor/m1", 40, ns(5), "monitor.observation")


def runner(speed=9.0, lag=1.0, hz=5):
    """A car crossing on red `lag` s after red; returns the passage and the crossing time (s)."""
    motion = Motion(-90, speed)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("173")
    run.lights("J1", "west", [(0, "green"), (crossing - lag - 3, "amber"), (crossing - lag, "red"),
                              (crossing + 2, "red_amber"), (crossing + 4, "green")])
    run.drive("173", motion, "west", rate(hz, 0, crossing + 6))
    return history.from_events(run.events, "173")[0], crossing


# --- contradictions ---------------------------------------------------------------------------------

def test_a_stated_stop_contradicted_by_9_mps_is_a_contradiction_not_an_override():
    p, crossing = runner()
    facts, contradictions = derived.checked(p, ns(crossing - 1), [("173 is stopped.", STATED)])
    [c] = contradictions
    assert c.stated == "173 is stopped" and c.stated_by == STATED and "9.0 m/s" in c.measured
    assert not any(f.sentence.startswith("173 has speed of") for f in facts)       # held back
    assert c.to_finding().kind == "contradiction" and c.to_finding().evidence[0] == STATED
    assert c.evidence and all(r in p.evidence() for r in c.evidence)
    assert c.to_json()["detail"].startswith('"173 is stopped" was stated (monitor/m1 #40), but')


def test_a_stated_fact_that_agrees_is_no_contradiction():
    p, crossing = runner()
    facts, contradictions = derived.checked(p, ns(crossing + 0.2), [
        ("173 has red light", STATED), ("173 crossed the stop line on red light", STATED),
        ("173 has speed of 20", STATED), ("173 has crossed the stop line", STATED), ("the speed limit is 30", STATED)])
    assert contradictions == ()
    assert "173 crossed the stop line on red light" in {f.sentence for f in facts}


def test_the_light_a_car_entered_on_is_no_contradiction_once_it_is_over_the_line():
    """A stop-line camera keeps stating the light a car crossed on; the signal has changed since."""
    p, crossing = runner()
    _, contradictions = derived.checked(p, ns(crossing + 4.5), [("173 has red light", STATED)])
    assert contradictions == ()


def test_a_stated_green_where_the_signal_showed_red_is_a_contradiction():
    p, crossing = runner()
    facts, [c] = derived.checked(p, ns(crossing - 0.5), [("173 has green light", STATED)])
    assert "showed red" in c.measured and "173 has red light" not in {f.sentence for f in facts}


def test_stated_speed_limit_crossing_and_emergency_contradictions():
    p, crossing = runner()
    _, found = derived.checked(p, ns(crossing - 2), [
        ("the speed limit is 40", STATED), ("173 has crossed the stop line", STATED),
        ("173 has speed of 50", STATED), ("173 crossed the stop line on green light", STATED)])
    assert sorted(c.stated for c in found) == ["173 has crossed the stop line", "173 has speed of 50",
                                               "the speed limit is 40"]
    _, [late] = derived.checked(p, ns(crossing + 1), [("173 crossed the stop line on green light", STATED)])
    assert "on red" in late.measured


def test_a_stated_stop_at_the_line_against_a_roll_through():
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop")], monitors=[])
    run.drive("7", Motion(-70, 10.0, [(3.0, -2.5), (4.0, 1.0)]), "west", rate(5, 0, 12))
    p = history.from_events(run.events, "7")[0]
    _, [c] = derived.checked(p, p.crossing.t + SECOND, [("7 has stopped at the stop line", STATED)])
    assert "without standing still" in c.measured


def test_hostile_stated_facts_are_ignored():
    p, crossing = runner()
    facts, found = derived.checked(p, ns(crossing), [(None, STATED), (42, STATED), ("173 has speed of lots", STATED),
                                                     ("x" * 10_000, STATED), ("", STATED)])
    assert found == () and facts


# --- provenance and the property tests ----------------------------------------------------------------

@settings(max_examples=60)
@given(speed=st.floats(3.0, 25.0), lag=st.floats(-3.0, 6.0), hz=st.sampled_from([2, 3, 5, 7, 10]),
       jitter=st.booleans(), seed=st.integers(0, 10_000))
def test_the_crossing_lies_between_its_samples_and_facts_cite_only_the_passage(speed, lag, hz, jitter, seed):
    motion = Motion(-95, speed)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("7", emergency=seed % 2 == 0)
    run.spawn("8")
    run.lights("J1", "west", [(0, "green"), (crossing - lag - 3, "amber"), (crossing - lag, "red")])
    end = crossing + 5
    times = irregular(0, end, seed=seed, low=0.1, high=0.5) if jitter else rate(hz, 0, end)
    run.drive("7", motion, "west", times)
    run.drive("8", Motion(-80, 12.0, [(crossing - 3, 0.0), (3.0, -3.0)]), "north", rate(hz, 0, end))
    p = history.from_events(run.events, "7")[0]
    c = p.crossing
    assert c is not None
    a, b = c.moment.used
    assert a.t <= c.t <= b.t and p.line.to_line(a.x, a.y) >= -LINE_EPS_M > p.line.to_line(b.x, b.y)
    # steady speed: exact, but for the 5 cm a sample may lie past the line and still count as on it
    assert abs(c.t - ns(crossing)) <= LINE_EPS_M / speed * SECOND + (b.t - a.t) // 50 + 2_000_000
    evidence = p.evidence()
    for at in (p.start, c.t - SECOND // 3, c.t, c.t + 1, (c.t + p.end) // 2, p.end, p.end + SECOND):
        for f in derived.facts(p, at):
            assert f.evidence and set(f.evidence) <= evidence, f
            assert f.sentence == f.sentence.strip() and not f.sentence.endswith(".")


@settings(max_examples=40)
@given(st.lists(st.tuples(st.floats(-200, 200, allow_nan=False), st.floats(-200, 200, allow_nan=False),
                          st.floats(0, 40, allow_nan=False)), min_size=0, max_size=40),
       st.integers(2, 10))
def test_any_wandering_path_rebuilds_without_a_crash(points, hz):
    run = Foreign()
    run.lights("J1", "west", [(0, "green"), (2, "amber"), (5, "red")])
    for i, (x, y, v) in enumerate(points):
        run.emit("vehicle/7", ns(i / hz), "entity.state", {"x": x, "y": y, "speed_mps": v})
    for p in history.from_events(run.events, "7"):
        for f in derived.facts(p, p.start + (p.end - p.start) // 2):
            assert set(f.evidence) <= p.evidence()


# --- the sentences are the rulebooks' -----------------------------------------------------------------

WRITTEN = [vocab.WOULD_FORCE, vocab.CROSSED_THE_STOP_LINE_ON]


@pytest.mark.parametrize("sentence", WRITTEN, ids=lambda s: s.functor)
def test_the_new_sentences_read_back_in_their_rulebook(sentence):
    rb = get_engine().load(bundled(sentence.rulebook), sentence.rulebook)
    assert rb.document.template_for(sentence.functor, sentence.arity) is not None
    args = (173, "red") if sentence is vocab.CROSSED_THE_STOP_LINE_ON else (173, 254)
    assert parse_fact(sentence.text(*args), rb.document.templates) == sentence.atom(*args)


def test_every_sentence_a_passage_shows_reads_in_a_rulebook():
    """All the sentences the scenarios above derive, read by highway_code.le or monitors.le
    (the sentences' names are reasoner/vocabulary.py's)."""
    books = [get_engine().load(bundled(n), n) for n in ("highway_code.le", "monitors.le")]
    p, crossing = runner()
    shown = {f.sentence for at in (crossing - 3.5, crossing - 0.5, crossing + 0.5) for f in derived.facts(p, ns(at))}
    for sentence in shown:
        assert any(parse_fact(sentence, b.document.templates) for b in books), sentence


# --- rule 126 ---------------------------------------------------------------------------------------------

def test_stopping_distances_are_rule_126s_at_its_rows_and_between_them():
    for speed, thinking, braking, overall in stopping.TABLE:
        assert stopping.stopping_distance_m(speed) == pytest.approx(overall)
        assert stopping.thinking_m(speed) == pytest.approx(thinking)
    assert 12 < stopping.stopping_distance_m(25) < 23 and stopping.stopping_distance_m(0) == 0
    speeds = [s / 2 for s in range(0, 200)]
    assert all(stopping.stopping_distance_m(a) < stopping.stopping_distance_m(b) for a, b in zip(speeds, speeds[1:]))


def test_the_table_is_the_legal_texts():
    text_file = Path(__file__).parents[2].parent.parent / "shared" / "highway-code" / "road-junctions-170-183.md"
    if not text_file.exists():
        text_file = Path("/work/shared/highway-code/road-junctions-170-183.md")
    if not text_file.exists():
        pytest.skip("the shared legal texts are not beside this checkout")
    rows = re.findall(r"\| (\d+) mph \| (\d+) m \| (\d+) m \| (\d+) m \|", text_file.read_text(encoding="utf-8"))
    assert tuple(tuple(int(x) for x in row) for row in rows) == stopping.TABLE


def test_a_margin_without_method_reads_as_before():
    ref = EventRef("r", "vehicle/1", 1, 2, "entity.state")
    assert Margin("mph over the speed limit", 8.0, "mph", (ref,)).to_json() == {
        "quantity": "mph over the speed limit", "value": 8.0, "unit": "mph", "evidence": [ref.to_json()]}


def test_speed_is_rounded_half_up_to_whole_mph():
    from reasoner.history import mph
    assert [mph(x / MPH_PER_MPS) for x in (29.49, 29.5, 30.0, 0.49, 0.5)] == [29, 30, 30, 0, 1]


def test_a_passage_is_json():
    import json
    p, _ = runner()
    data = json.loads(json.dumps(p.to_json()))
    assert data["crossing"]["light"]["colour"] == "red" and data["vehicle"] == "173"
    assert data["junction"]["stop_lines"][0]["source"] == "map stop_lines"
    assert T0 < data["crossing"]["t"]


# --- what a map-only producer needs derived (tests/reasoner/test_foreign_scenarios.py) -----------------

def _through(junction, motion, approach="west", hz=2, end=20.0, others=()):
    run = Foreign(junctions=[junction], monitors=[])
    run.spawn("7")
    for who, kind, other_motion, other_approach in others:
        run.spawn(who, kind, role="pedestrian" if kind == "pedestrian" else "vehicle")
        run.drive(who, other_motion, other_approach, rate(hz, 0, end), role="pedestrian" if kind == "pedestrian" else "vehicle")
    run.drive("7", motion, approach, rate(hz, 0, end))
    return run


@pytest.mark.parametrize("control,kind,sign", [("stop", "stop", "stop"), ("give_way", "give_way", "give way"),
                                               ("stop", "", "stop"), ("lights", "signal", None)])
def test_the_maps_stop_or_give_way_line_gives_the_sign(control, kind, sign):
    """DESIGN's map marks a Stop or Give Way line by its kind (or the junction's control); a producer
    that draws the map states no sign at every frame, so `V has a S sign` is derived from it (the
    monitors' HC 171 and HC 172 rules need it: without it a measured-only run raised neither)."""
    run = _through(crossroads("J1", 0.0, 0.0, control, kinds={"west": kind, "east": kind}), Motion(-60, 8.0))
    p = history.from_events(run.events, "7")[0]
    signs = [f for f in derived.facts(p, p.crossing.t - SECOND) if " sign" in f.sentence]
    assert [f.sentence for f in signs] == ([f"7 has a {sign} sign"] if sign else [])
    assert all(f.evidence == (p.map_ref,) for f in signs)


def test_a_stop_short_of_the_junction_past_a_worn_line_is_a_stop_before_the_major_road():
    """Sch 9 Pt 7 para 1: with the line not clearly visible, the stop is owed "before entering the
    major road". A car standing 1.5 m past a Stop line drawn 16 m out, short of the junction's
    12 m edge, stopped before entering the major road, not at the line; one rolling through did
    neither."""
    j = crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop", "north": ""})
    west = next(line for line in j["stop_lines"] if line["approach"] == "west")
    west["from"], west["to"] = [-16.0, 0.0], [-16.0, 3.5]
    stops = Motion.stopping_at(-60.0, 10.0, -14.5, wait=3.0, then=10.0)
    p = history.from_events(_through(j, stops, hz=5).events, "7")[0]
    shown = {f.sentence for f in derived.facts(p, p.entered.t + SECOND)}
    assert "7 has stopped before entering the major road" in shown
    assert "7 has stopped at the stop line" not in shown
    assert "7 has stopped before entering the major road" not in {   # not before it stood still
        f.sentence for f in derived.facts(p, p.crossing.t + SECOND // 10)}
    rolls = history.from_events(_through(j, Motion(-60.0, 10.0, [(3.0, -2.0)]), hz=5).events, "7")[0]
    assert "7 has stopped before entering the major road" not in {
        f.sentence for f in derived.facts(rolls, rolls.entered.t + SECOND)}


def test_another_road_users_type_comes_with_it_approaching():
    """TSRGD para 5(5) "likely to endanger any person": highway_code.le reads `U is approaching V`
    with `U is of type pedestrian` (or cyclist); the type is in U's entity.spawn, which the
    history now reads for the other road users, from a list of events and from a store alike.
    p1 walks north across 7's lane (y = +1.75) as 7 (9 m/s from 60 m west) gets there, 6.47 s in:
    in 7's path as it comes, so approaching it (issue 35: not merely walking towards the junction)."""
    walker = Motion(1.75 - 1.4 * (58.25 / 9.0), 1.4)
    run = _through(crossroads("J1", 0.0, 0.0, "lights"), Motion(-60.0, 9.0), hz=5, end=12.0,
                   others=[("p1", "pedestrian", walker, "south")])
    run.lights("J1", "west", [(0, "red")])
    p = history.from_events(run.events, "7")[0]
    facts = {f.sentence: f for f in derived.facts(p, p.crossing.t)}
    assert "p1 is approaching 7" in facts and "p1 is of type pedestrian" in facts
    spawn = next(e for e in run.events if e["src"] == "pedestrian/p1" and e["kind"] == "entity.spawn")
    assert [r.key for r in facts["p1 is of type pedestrian"].evidence] == [("pedestrian/p1", spawn["seq"])]
    import tempfile
    from store import Store
    with tempfile.TemporaryDirectory() as d, Store(Path(d) / "s.db") as s:
        s.append(run.events)
        stored = history.passage(s, run.run, "7", p.crossing.t)
        assert "p1 is of type pedestrian" in {f.sentence for f in derived.facts(stored, p.crossing.t)}


def test_the_amber_margin_says_when_the_light_at_the_crossing_is_uncertain():
    """The signal's red report is lost: the crossing reads amber, with a signal event missing; the
    amber margin (metres from the line when amber came) carries that doubt, as the red one does."""
    from reasoner import margins
    motion = Motion(-90, 12.5)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (crossing - 3.4, "amber"), (crossing - 0.4, "red"),
                              (crossing + 8, "red_amber"), (crossing + 10, "green")])
    run.drive("7", motion, "west", rate(5, 0, crossing + 5))
    run.drop("signal/J1-west", [2])
    p = history.from_events(run.events, "7")[0]
    m = margins.margin(p, "enter the junction")
    assert p.crossing.light.colour == "amber" and m.unit == "m"
    assert m.uncertain and "signal/J1-west event 2 missing" in m.uncertain
