"""The reasoner's "forced / endangered" beside SUMO's own account of a run, incident by incident.

bench/conflict_agreement.py prints the table; this is its comparison, kept with the tests' other
oracle (tests/helpers/sim_truth_table.py, whose matching of incidents to acts it uses) so that a
test can hold a run to it too. The truth is the simulation's (sim_replay/truth.py, with SUMO's
account: sim_replay/sumo_account.py); the reasoner's incidents are read only to be compared.

    reasoner    the road users its proofs name: "V would force U to change speed or course",
                "V would endanger U" (a sentence of that shape standing as a fact or proved in the
                potential violation's tree or the verdict's, or among the facts the history
                derived for the incident: a proof shows one road user where several are named)
    SUMO        the road users SUMO says braked for V about its crossing (the truth's
                act.sumo.yielded: cause a junction foe V, or V as a leader that had joined their
                road from another arm) at HARD_BRAKING or harder held over a second, or to a
                stop from moving, under that cause (`gave_way`), and the pedestrians in V's path over a
                crossing within crossing_paths.WINDOW_S of V (act.sumo.in_path, with the PET; a truth
                kept before that lists every pedestrian on a crossing SUMO makes a foe of V's junction
                lane while V passed, and is read so), less a braking to stand at the road user's own
                Stop line (`to_own_stop_line`): the law's own control, which SUMO's model may hold
                on a foe as well

A false accusation is a road user the reasoner names and SUMO does not; a miss, one SUMO names and
the reasoner does not. A miss is "not proven" instead where the reasoner measured the same braking
SUMO holds to V and said why it did not name it: the braking is "in doubt" (its measured figure less
its uncertainty under the threshold), and SUMO's own figure lies within that measured figure ±
its uncertainty. The record then agrees with SUMO on what happened; what parts them is the
standard of proof ("where the deciding fact is in doubt, it is not proven"), which SUMO's exact
figure does not have to meet. It is counted apart, never as agreeing.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from sim_replay.sim_events import T0
from sim_replay.truth import ABOUT_S, yielded_to
from tests.helpers.sim_truth_table import compare as lines_of

__all__ = ["HARD_BRAKING", "STANDSTILL_MPS", "Row", "compare", "gave_way", "in_doubt", "in_scope", "to_own_stop_line", "reasoner_grounds",
           "split_verdicts", "stated_cause", "sumo_gave_way"]

HARD_BRAKING = 2.0      # m/s²: a considerable change of speed (Hupfer 1997), sim_truth_table's yardstick too
STANDSTILL_MPS = 0.5    # braking down to this for V is giving way to it however gently
_GROUND = re.compile(r"^(?P<v>\S+) (?:would )?(?:force|forces|forced|endanger|endangers|endangered) (?P<u>\S+)")
def reasoner_grounds(incident: Any) -> set[str]:
    """The road users the incident's verdict names as forced or endangered by its vehicle."""
    named: set[str] = set()

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            text = node.get("text")
            if isinstance(text, str) and node.get("status") in ("proved", "fact"):
                m = _GROUND.match(text.strip().rstrip("."))
                if m and m["v"] == incident.vehicle:
                    named.add(m["u"])
            for child in node.get("children", ()):
                walk(child)
        elif isinstance(node, list):
            for item in node:
                walk(item)

    for stage in incident.proofs.to_json().values():
        walk(stage.get("trees", []))
    walk([{"text": d.sentence, "status": "fact"} for d in incident.derived])
    return named


def gave_way(y: dict[str, Any]) -> bool:
    """Whether a braking SUMO puts down to V (truth.yielded_to) was giving way to V, measured as the
    threshold is stated: HARD_BRAKING held over a second (the speed SUMO says it shed under V's
    cause within one second, sumo_account.HELD_S), or a stop for V from moving: down to
    STANDSTILL_MPS, having shed at least what a second of HARD_BRAKING sheds under that cause. A
    one-tick peak (7.3 to 6.5 m/s at 4.5 m/s² for a tick) is no considerable change of speed, nor
    a creep from 0.5 m/s to standing. A truth kept before SUMO's account measured the held braking
    (no held_mps2) is read by its peak in a tick, as it then was."""
    if y.get("held_mps2") is None:
        return y["decel_mps2"] >= HARD_BRAKING or y["min_speed_mps"] <= STANDSTILL_MPS
    stopped = y["min_speed_mps"] <= STANDSTILL_MPS and (y.get("from_mps") or 0.0) - y["min_speed_mps"] >= HARD_BRAKING
    held = max(y["held_mps2"], y.get("road_user_held_mps2") or 0.0)    # V under all its causes, as one
    return held >= HARD_BRAKING or stopped


def sumo_gave_way(act: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Who SUMO says gave way to the act's vehicle (`gave_way`) or was in its path."""
    out: dict[str, dict[str, Any]] = {}
    for y in act.get("sumo", {}).get("yielded", []):
        if gave_way(y):
            seen = out.get(y["vehicle"])
            if seen is None or y["decel_mps2"] > seen["decel_mps2"]:
                out[y["vehicle"]] = y
    for who, crossing, away, *gap in act.get("sumo", {}).get("in_path", []):
        out.setdefault(who, {"vehicle": who, "cause": "pedestrian in its path", "crossing": crossing,
                             "nearest_m": away, "pet_s": gap[0] if gap else None})
    return out


def stated_cause(truth: dict[str, Any], who: str, act: dict[str, Any]) -> str:
    """SUMO's account of what `who` braked for about the act (from the truth's yields only)."""
    t = act["t_s"]
    mine = [y for y in truth.get("yields", []) if y["vehicle"] == who and t - ABOUT_S[0] <= y["t_s"] <= t + ABOUT_S[1]]
    if not mine:
        if truth["road_users"].get(who, {}).get("type") == "pedestrian":
            return "a pedestrian not in its path over a crossing within the window"
        return "did not brake about then"
    parts = []
    for y in mine:
        causes = ", ".join(f"{k} {c['decel_mps2']:.1f} m/s²" + (f" (held {c['held_mps2']:.1f})" if "held_mps2" in c else "")
                           for k, c in sorted(y["causes"].items(), key=lambda kv: -kv[1].get("held_mps2",
                                                                                            kv[1]["decel_mps2"])))
        parts.append(f"{y['t_s']:.1f}-{y['until_s']:.1f}s: {causes}")
    return "; ".join(parts)


@dataclass
class Row:
    """One in-scope incident, the road users each side names, and where they differ."""

    incident: Any
    act: dict[str, Any]
    reasoner: set[str]
    sumo: dict[str, dict[str, Any]]
    truth: dict[str, Any] = field(default_factory=dict, repr=False)
    false: list[str] = field(default_factory=list)
    missed: list[str] = field(default_factory=list)
    not_proven: list[str] = field(default_factory=list)

    @property
    def agrees(self) -> bool:
        return not self.false and not self.missed and not self.not_proven


def in_scope(act: dict[str, Any] | None) -> bool:
    """Stop, Give Way and emergency-red crossings."""
    return act is not None and act["kind"] == "crossed the stop line" and (
        act["line"] in ("stop", "give_way") or (act["light"] in ("red", "red_amber") and act["on_call"]))


def compare(truth: dict[str, Any], incidents: list[Any]) -> tuple[list[Row], list[dict[str, Any]]]:
    """Each in-scope incident beside SUMO's account; and the in-scope acts a monitor saw that have
    no incident although SUMO says someone gave way to them (unraised)."""
    rows, unraised = [], []
    for line in lines_of(truth, incidents, T0):
        if not in_scope(line.act):
            continue
        act = _afresh(line.act, truth)
        sumo = {u: y for u, y in sumo_gave_way(act).items() if not to_own_stop_line(truth, u, y)}
        if not line.incidents and act["seen_by"] and sumo:
            unraised.append(act)
        for inc in line.incidents:
            row = Row(inc, act, reasoner_grounds(inc), sumo, truth)
            row.false = sorted(row.reasoner - set(row.sumo))
            unnamed = sorted(set(row.sumo) - row.reasoner)
            row.not_proven = [u for u in unnamed if in_doubt(inc, u, row.sumo[u])]
            row.missed = [u for u in unnamed if u not in row.not_proven]
            rows.append(row)
    return rows, unraised


def to_own_stop_line(truth: dict[str, Any], user: str, y: dict[str, Any]) -> bool:
    """Whether SUMO's braking of `user` for V was a braking to stand at its own Stop line: its own
    line binds in the same stretch of braking (SUMO's account names it among the causes), and the
    road user's next crossing of a line is of a Stop line at which it stood. TSRGD 2016 Sch 9 Pt 7
    para 1 requires every vehicle to stop at that line whoever comes, so that braking is its own
    control (issue 35: "not for its own control (its own signal, Stop or Give Way line ...)"),
    however SUMO's model apportions it: its junction model holds a car at its line for a foe in the
    junction too (paper-11 267 for 195, paper-12 142 for 155, branch line35). A Give Way line asks
    no stop where the way is clear, so it is not read so."""
    t = y.get("t_s")
    if t is None or "cause" not in y or y["cause"] == "pedestrian in its path":
        return False
    stretch = next((s for s in truth.get("yields", ()) if s["vehicle"] == user and s["t_s"] <= t <= s["until_s"]), None)
    if stretch is None or "line" not in stretch.get("causes", {}):
        return False
    after = [a for a in truth.get("acts", ()) if a["vehicle"] == user and a["kind"] == "crossed the stop line"
             and a["t_s"] >= stretch["t_s"]]
    nxt = min(after, key=lambda a: a["t_s"], default=None)
    return nxt is not None and nxt["line"] == "stop" and bool(nxt["stopped_at_line"])


def in_doubt(incident: Any, user: str, sumo: dict[str, Any]) -> bool:
    """Whether the incident clears `user` of the second limb as "in doubt" with a measured braking
    whose uncertainty band holds SUMO's own held figure for it (the module docstring)."""
    held = max(sumo.get("held_mps2") or 0.0, sumo.get("road_user_held_mps2") or 0.0)
    for u in getattr(incident, "second_limb", ()) or ():
        if u.user == user and u.reason == "in doubt" and u.decel_mps2 is not None \
                and u.decel_uncertainty_mps2 is not None and held > 0.0:
            return abs(held - u.decel_mps2) <= u.decel_uncertainty_mps2
    return False


def _afresh(act: dict[str, Any], truth: dict[str, Any]) -> dict[str, Any]:
    """The act with who SUMO says braked for it read again from the truth's yields by today's
    sim_replay.truth.yielded_to, where the truth's account measured the held braking (a truth
    kept before that is read as it was kept)."""
    yields = truth.get("yields")
    if "sumo" not in act or not yields or not any("held_mps2" in c for y in yields[:100]
                                                  for c in y.get("causes", {}).values()):
        return act
    return {**act, "sumo": {**act["sumo"], "yielded": yielded_to(act, yields, truth.get("conflicts") or [])}}


def split_verdicts(truth: dict[str, Any], incidents: list[Any]) -> list[tuple[dict[str, Any], list[Any]]]:
    """Acts (the truth's, matched as sim_truth_table matches them) judged by more than one
    incident with different verdicts or rules: one act, opposite verdicts (issue 35: one crossing,
    the same margin, £50 in one incident and lawful in the next). Empty when every act has one
    verdict, whichever monitor's incident carries it."""
    out = []
    for line in lines_of(truth, incidents, T0):
        if line.act is None:
            continue
        same = [i for i in line.incidents if _at(i, line.act)]
        if len({(i.verdict, i.rule) for i in same}) > 1:
            out.append((line.act, same))
    return out


def _at(incident: Any, act: dict[str, Any]) -> bool:
    """Whether the incident is of the act itself, where its record says when: its passage crossed
    its line at the act's crossing (within a second or two: the record's moment against SUMO's
    tick), or the stretch it delimits began within the act's stretch over the limit. A vehicle's
    next crossing at another junction, or its next stretch, within the matching window is another act."""
    if act["kind"] == "crossed the stop line":
        crossed = dict(getattr(incident, "moments", ()) or ()).get("crossed the stop line")
        return crossed is None or abs((crossed - T0) / 1e9 - act["t_s"]) <= 2.0
    delimited = getattr(incident, "act", None)
    start = getattr(delimited, "start", None)
    if start is None or act.get("until_s") is None:
        return True
    return act["t_s"] - 2.0 <= (start - T0) / 1e9 <= act["until_s"]
