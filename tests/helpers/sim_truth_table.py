"""From the simulation's ground truth to the verdicts the law should give: a small table, read top down.

The simulation records acts, never verdicts (sim_replay/truth.py). This table is the test's own
reading of the law, one row per kind of act and circumstance, each citing its source; the first
row that fits an act gives the expected verdict and rule (None: no incident expected).
`compare` matches the reasoner's incidents to the acts and lists every disagreement; KNOWN holds
the disagreements that are known and explained (a line's `known`), findings about the reasoner and
its rulebooks rather than tuned away in the simulation; any other is unexplained.

Measured circumstances use published yardsticks, named where used: "braked hard" is 2 m/s² or
more (Hupfer 1997, the threshold the reasoner's derived.py cites for a forced change of speed);
"too close to stop" at amber is nearer than the Highway Code rule 126 stopping distance at the
speed the vehicle had when the amber came.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from reasoner.stopping import stopping_distance_m

MPH = 2.23694
HARD_BRAKING = 2.0
SECOND = 1_000_000_000


# Who counts as "about" an act: every road user the simulation's witness recorded approaching as V
# crossed its line, or coming up while V was still in the junction ("(+1.7s)": sim_replay/witness.py
# adds them only then). V's crossing lasts until it is through: a main-road driver who comes up while
# a car that pulled away from its line is still crossing, and has to brake for it, was made to change
# speed by that crossing (TSRGD 2016 Sch 9 Pt 7 para 1, Sch 14 Pt 1 para 5(5): "so as to be likely
# to ... cause the driver of another vehicle to change its speed or course"), the reading the
# reasoner's history takes too (braking counted until 3 s after V left). This table once left out
# those that came up more than a second after V crossed, and listed the resulting disagreements
# as known; that was the table's reading, not the law's.


def _main(act: dict) -> set[str]:
    """The major-road users approaching V as it crossed its line, or coming up while it crossed."""
    return {a.split()[0] for a in act["approaching"] if " main " in a}


def _vulnerable(act: dict) -> set[str]:
    return {a.split()[0] for a in act["approaching"] if a.split()[1] in ("pedestrian", "cyclist")}


def braked(act: dict, who: set[str] | None = None) -> bool:
    """Whether a road user about the act (of `who`; default: all of them) braked hard after it."""
    there = {a.split()[0] for a in act["approaching"]} if who is None else who
    return any(d >= HARD_BRAKING for r, d in act["reactions"].items() if r in there)


def too_close_at_amber(act: dict) -> bool:
    if not act.get("at_amber"):
        return True                                     # over the line before the amber came
    to_line, speed = act["at_amber"]
    return to_line < stopping_distance_m(speed * MPH)


def signal(act: dict, *colours: str) -> bool:
    return act["kind"] == "crossed the stop line" and act["line"] == "signal" and act["light"] in colours


def line(act: dict, kind: str) -> bool:
    return act["kind"] == "crossed the stop line" and act["line"] == kind


@dataclass(frozen=True)
class Row:
    name: str
    fits: Callable[[dict], bool]
    verdict: str | None
    rule: str | None


def against_its_rulebook(a: dict) -> bool:
    """It asked, its rulebook said it could not enter, and it went on (too late to stop)."""
    d = a.get("decision") or {}
    return a["kind"] == "crossed the stop line" and d.get("permitted") is False and d.get("proceeds") is True

TABLE = (
    # DESIGN "Reasoning": the Vehicle Scenario is the vehicle's own; on it, its own rulebook forbade the act
    Row("went on against its own rulebook at a red light", lambda a: against_its_rulebook(a) and signal(a, "red", "red_amber"),
        "punishable", "HC 176"),
    Row("went on against its own rulebook at a Stop line", lambda a: against_its_rulebook(a) and line(a, "stop"),
        "punishable", "HC 171"),
    Row("went on against its own rulebook at a Give Way line", lambda a: against_its_rulebook(a) and line(a, "give_way"),
        "punishable", "HC 172"),
    Row("crossed on green", lambda a: signal(a, "green", None, "off", "none"), None, None),
    # HC 176; TSRGD 2016 Sch 14 Pt 1 para 5(3) and (7): no proceeding beyond the line on red (or red and amber)
    Row("crossed on red, no call", lambda a: signal(a, "red", "red_amber") and not a["on_call"], "punishable", "HC 176"),
    # TSRGD para 5(5): on a call, but endangering a pedestrian or cyclist or forcing a driver to brake
    Row("crossed on red on a call, someone endangered or forced",
        lambda a: signal(a, "red", "red_amber") and (bool(_vulnerable(a)) or braked(a)), "punishable", "HC 176"),
    # TSRGD para 5(4)-(6): the emergency exception
    Row("crossed on red on a call, nobody endangered", lambda a: signal(a, "red", "red_amber"), "mitigated", "HC 176"),
    # HC 175: amber means stop, unless so close that stopping might cause a collision
    Row("crossed on amber, too close to stop", lambda a: signal(a, "amber") and too_close_at_amber(a),
        "mitigated", "HC 175"),
    Row("crossed on amber, could have stopped", lambda a: signal(a, "amber"), "punishable", "HC 175"),
    # HC 171; TSRGD 2016 Sch 9 Pt 7 para 1: stop at the Stop line
    Row("over a Stop line without stopping", lambda a: line(a, "stop") and not a["stopped_at_line"],
        "punishable", "HC 171"),
    # HC 171: having stopped, do not pull out so that traffic on the major road must change speed
    Row("stopped at a Stop line, then forced major-road traffic to brake",
        lambda a: line(a, "stop") and braked(a, _main(a)), "punishable", "HC 171"),
    Row("stopped at a Stop line, pulled out into a gap", lambda a: line(a, "stop"), None, None),
    # HC 172; TSRGD 2016 Sch 9 Pts 7 and 8: give way to traffic on the major road
    Row("out of a Give Way line, major-road traffic braked hard", lambda a: line(a, "give_way") and braked(a, _main(a)),
        "punishable", "HC 172"),
    Row("out of a Give Way line, major-road traffic approaching, nobody braked",
        lambda a: line(a, "give_way") and bool(_main(a)), "mitigated", "HC 172"),
    Row("out of a Give Way line, major road empty", lambda a: line(a, "give_way"), None, None),
    # HC 124; RTRA 1984 s.89, and s.87's exemption for emergency purposes
    Row("over the limit on a call", lambda a: a["kind"] == "exceeded the speed limit" and a["on_call"],
        "mitigated", "HC 124"),
    Row("over the limit", lambda a: a["kind"] == "exceeded the speed limit", "punishable", "HC 124"),
    # HC 174; TSRGD 2016 Sch 9 Pts 7 and 8: do not enter the box unless the exit is clear
    Row("stood still in a yellow box, its exit blocked", lambda a: a["kind"] == "stopped in the box" and a["exit_queue"],
        "punishable", "HC 174"),
    Row("stood still in a yellow box, its exit clear", lambda a: a["kind"] == "stopped in the box", None, None),
)

# (table row, what the reasoner gave) -> why they differ
KNOWN = {
    ("stopped at a Stop line, pulled out into a gap", "punishable HC 171"):
        "TSRGD 2016 Sch 9 Pt 7 para 1 forbids crossing a Stop line 'so as to ... cause the driver of another "
        "vehicle to change its speed or course': any other vehicle. The reasoner counts a car or bus from the "
        "opposite minor arm that came to a stop or braked at 2 m/s² or more while V crossed (long-3: 269's pull-out "
        "stopped 155; 187's made bus 132 brake at 3.1 m/s²); this row, as its name says, counts only major-road "
        "traffic, since the witness's braking figure (SUMO's one-tick deceleration) does not tell a minor-road "
        "car slowing for its own Give Way line from one made to brake. Where two vehicles emerge together "
        "(187 and 132), a main-road car's braking is credited to both by the reasoner, to the one that turned in "
        "front of it by the witness. A main-road car that began to slow within the 2.5 s perception-reaction time "
        "after V left its lane is counted by the reasoner, whose window runs until 3 s after V left the junction, "
        "and not by the witness, which looks 3 s after V crossed its line (long-6: 147 began to slow 2.2 s after "
        "256 had crossed its lane, 55 m ahead of it).",
    ("stopped at a Stop line, then forced major-road traffic to brake", "no incident"):
        "the witness counts a main-road car's hard braking in the 3 s after V crossed when that car's way joins "
        "V's, whatever it braked for; the reasoner reads both ways and finds the car braked for a turn of its own "
        "into the road V had gone down, with V already far ahead of it, going its way (the two-second gap behind V "
        "could be kept braking at under 2 m/s², reasoner/reaction.py `well_ahead`): it was not made to brake by "
        "V (TSRGD 2016 Sch 9 Pt 7 para 1: 'in order to avoid an accident'). long-6: 224 braked at 4.5 m/s² to "
        "wait for oncoming 195 before turning right into j2's south arm, while 285, out of the north Stop line, "
        "was 16 m down that arm at 11.9 m/s. Known only when every car the witness saw brake leaves by V's exit",
    ("out of a Give Way line, major-road traffic approaching, nobody braked", "punishable HC 172"):
        "the main-road car braked hard within the 3 s after V left the junction that the reasoner counts, as a "
        "second vehicle pulled out of the opposite Stop line (long-3: 265 braked at 4.5 m/s² 1.4 s after 155 "
        "left, as 147 crossed; the witness credits the braking to 147's act): the history cannot tell which of "
        "two vehicles crossing one after the other a road user braked for",
    ("went on against its own rulebook at a Stop line", "no incident"):
        "the vehicle stopped at its line, then went on though its rulebook said it must not: its perception "
        "stated a pedestrian on a crossing 'approaching' it (long-3: 230 and p7, who was crossing the east arm, "
        "not 230's north-south path), which highway_code.le reads as 'likely to endanger' (para 5(5)'s reading, "
        "which its HC 171 rule uses too). Nobody changed speed for it (measured), and monitors.le raises the "
        "second limb of para 1 only on a measured or stated forcing or a stated endangerment, not on every "
        "pedestrian near the junction (that would make most lawful Stops potential violations): no potential "
        "violation, so no incident, and the decision fault (it went on against its own rulebook) has no incident "
        "to be found on",
    ("out of a Give Way line, major-road traffic braked hard", "mitigated HC 172"):
        "the table's braking figure is SUMO's deceleration over one 0.1 s tick (town-4m: 296 at 4.5 m/s² as 249 "
        "pulled out of j10's Give Way line); the reasoner measures a change of speed over at least a second of "
        "samples (reasoner/motion.py MIN_DECEL_SPAN_S: 296 went from 13.4 to 12.7 m/s, 0.7 m/s²), below the "
        "2 m/s² of a considerable reaction (Hupfer 1997): a dab of the brakes is not being made to change speed, "
        "so on the rules 249's exit was lawful. Known only when the incident's measured deceleration is below "
        "that yardstick",
    ("crossed on amber, could have stopped", "mitigated HC 175"):
        "an automated car judged itself 'too close to the stop line to stop safely' and went on at amber; the "
        "Validator Scenario is its own view (a camera witnesses no such judgement). Where its record contradicts "
        "the belief beyond the measurements' tolerance (town-4m: 163 was 28.7 m from the line at 30 mph when "
        "amber came; rule 126: 23 m) the claim decides nothing and the verdict is punishable on the measurements "
        "(DESIGN 'Weighing'), agreeing with the truth; known here only where a contradiction finding remains on "
        "a mitigated incident",
    ("crossed on amber, too close to stop", "punishable HC 175"):
        "a boundary case of measurement: the act's distance when amber came is short of rule 126's stopping "
        "distance, the reasoner's is beyond it, by less than the vehicle travels in one of the simulation's 0.1 s "
        "ticks (town-1h: 1534 at 30 mph, 22.48 m in the truth, 23.82 m measured, 23 m needed). The witness takes "
        "the position at the end of the first tick the amber shows; the reasoner interpolates the vehicle's "
        "samples to the signal's event time. Neither is finer than a tick, so which side of the yardstick the act "
        "falls is not decided by the record. Known only when the incident's margin is within one tick's travel",
    ("crossed on amber, too close to stop", "dismissed HC 175"):
        "the boundary case above (the act's distance within one tick's travel of rule 126's stopping distance): "
        "the margin does not exceed its uncertainty, so the reasoner finds the conviction not proven (dismissed, "
        "DESIGN 'Margins'); the truth, read at the end of a tick, has it too close to stop (mitigated). No penalty "
        "either way. Known only when the incident's margin is within one tick's travel",
    (None, "dismissed HC 124"):
        "the camera's speed reading was high (the injected speed_error fault: 12-30 % over) while the vehicle's "
        "own entity.state speeds are under the limit: the potential violation rests on the camera's sentence, "
        "which the measurements contradict beyond tolerance, so it is not proven (dismissed, DESIGN 'Weighing'), "
        "with a contradiction finding on the speed. The truth has no act. Known only with that finding",
    (None, "punishable HC 124"):
        "the camera's speed reading was high (the injected speed_error fault: 12-30 % over) and contradicted by "
        "the vehicle's own record, which is itself over the limit by the reasoner's reading of its stretch: the "
        "verdict does not turn on the contradiction (DESIGN 'Weighing'), so it stands, with a contradiction "
        "finding on the speed. Known only with that finding",
}


def _speed_in_doubt(line: "Line") -> bool:
    """A speeding incident with no act behind it whose speed the vehicle's own record contradicts."""
    return all(i.action == "exceed the speed limit" and any(
        f.kind == "contradiction" and f.fact and " has speed of " in f.fact for f in i.findings)
        for i in line.incidents)


def _braked_gently(line: "Line") -> bool:
    """Every incident of the line measured the other road user's deceleration below HARD_BRAKING."""
    return bool(line.incidents) and all(
        i.margin is not None and i.margin.quantity == "deceleration of the other road user"
        and i.margin.value < HARD_BRAKING for i in line.incidents)


TICK_S = 0.1     # the simulation's step: the witness reads the world once a tick


def _amber_within_a_tick(line: "Line") -> bool:
    """Every incident's amber margin is beyond rule 126's stopping distance by less than the
    vehicle travelled in one tick at its speed when amber came (the act's own figure is short of it)."""
    def close(i) -> bool:
        m = i.margin
        if m is None or m.quantity != "metres from the stop line when amber came":
            return False
        figures = {q: v for q, v, _ in m.figures}
        beyond, mph = figures.get("distance beyond what stopping takes"), figures.get("speed when amber came")
        return beyond is not None and mph is not None and 0 <= beyond < mph / MPH * TICK_S
    return bool(line.incidents) and all(close(i) for i in line.incidents)


def _belief_in_doubt(line: "Line", words: str) -> bool:
    """Every incident of the line carries a contradiction finding on a sentence with these words."""
    return bool(line.incidents) and all(any(f.kind == "contradiction" and f.fact and words in f.fact
                                            for f in i.findings) for i in line.incidents)


ACTION = {"crossed the stop line": "enter the junction", "exceeded the speed limit": "exceed the speed limit",
          "stopped in the box": "enter the box junction"}


def expected(act: dict) -> Row:
    return next(row for row in TABLE if row.fits(act))


@dataclass
class Line:
    """One act (or one incident without an act) and how the reasoner judged it."""

    act: dict[str, Any] | None
    row: Row | None
    incidents: list[Any]
    seen: bool                      # a monitor had it in its cone
    braked_behind: bool = False     # every road user that braked hard after the act leaves by the act's exit

    @property
    def got(self) -> tuple[tuple[str, str | None], ...]:
        return tuple(sorted({(i.verdict, i.rule) for i in self.incidents}))

    @property
    def got_text(self) -> str:
        return ", ".join(f"{v} {r}" for v, r in self.got) or "no incident"

    @property
    def known(self) -> str | None:
        """Why this disagreement is known (KNOWN), or None when it is not."""
        if self.row is None and not _speed_in_doubt(self):
            return None
        if self.row is not None and self.row.name == "crossed on amber, could have stopped" and \
                not _belief_in_doubt(self, " is too close to the stop line to stop safely"):
            return None
        if self.row is not None and self.row.name == "crossed on amber, too close to stop" and \
                not _amber_within_a_tick(self):
            return None
        if self.row is not None and self.row.name == "out of a Give Way line, major-road traffic braked hard" and \
                not _braked_gently(self):
            return None
        if self.row is not None and self.row.name == "stopped at a Stop line, then forced major-road traffic to brake" \
                and not self.braked_behind:
            return None
        return KNOWN.get((self.row.name if self.row else None, self.got_text))

    @property
    def agrees(self) -> bool:
        if self.act is None:
            return False
        if self.row.verdict is None:
            return not self.incidents
        if not self.incidents:
            return not self.seen        # an act no monitor saw may go unnoticed
        return all(g == (self.row.verdict, self.row.rule) for g in self.got)

    def describe(self) -> str:
        a = self.act
        if a is None:
            i = self.incidents[0]
            return f"(no act) {i.vehicle} {i.action} at {i.id}: {i.verdict} {i.rule}"
        where = f"{a['junction']}/{a['approach']} {a['line'] or ''}".strip() if a["junction"] else ""
        want = f"{self.row.verdict} {self.row.rule}" if self.row.verdict else "no incident"
        got = self.got_text
        return (f"{a['t_s']:7.1f}s {a['vehicle']:>4} {a['type']:<11} {a['kind']:<24} {where:<16} "
                f"light={a['light']} {a['speed_mph']}mph seen={','.join(a['seen_by']) or '-'} | {self.row.name} "
                f"| want {want} | got {got}")


def _braked_behind(act: dict, road_users: dict[str, dict]) -> bool:
    """Whether every road user that braked hard after the act has a route that leaves by the road
    the act's vehicle left by: it joined V's way behind V (its braking may be for a turn of its own)."""
    exit_ = road_users.get(act["vehicle"], {}).get("exit")
    hard = [r for r, d in act["reactions"].items() if d >= HARD_BRAKING]
    return bool(hard) and exit_ is not None and all(road_users.get(r, {}).get("exit") == exit_ for r in hard)


def compare(truth: dict, incidents: list, t0: int) -> list[Line]:
    """Every act beside the incidents of its vehicle and action in its time window, then the
    incidents no act accounts for."""
    lines, used = [], set()
    for act in truth["acts"]:
        action = ACTION[act["kind"]]
        start = act["t_s"] - 5.0            # a crossing is judged until the vehicle is through the junction
        end = (act["until_s"] if act["until_s"] is not None else act["t_s"]) + (5.0 if act["until_s"] else 15.0)
        found = [i for i in incidents if i.vehicle == act["vehicle"] and i.action == action
                 and start <= (i.t - t0) / SECOND <= end]
        used.update(i.id for i in found)
        lines.append(Line(act, expected(act), found, bool(act["seen_by"]), _braked_behind(act, truth["road_users"])))
    for i in incidents:
        if i.id not in used:
            lines.append(Line(None, None, [i], True))
    return lines
