"""The scene at a moment (reasoner/scene.py's `Scene`) as plain text lines, as `gaps scene` prints it.

Every line cites the event each fact came from ("vehicle/173 #2, +9.5s": source, seq, and the
offset from the run start), so the investigator can go from what is shown to what was recorded.
The lines hold recorded text as it was sent; the terminal's escaping is the command line's.
"""
from __future__ import annotations

from typing import Any

from reasoner.model import Cited, Control, Decision
from reasoner.scene import Scene, SceneFact, ValidatorShown, VehicleShown
from reasoner.when import format_offset, format_time
from store import EventRef

from .svg import SIGNAL_WORDS
from .units import speed_text

JUDGED_ON = {"vehicle scenario": "the Vehicle Scenario",
             "corrected vehicle scenario": "the Vehicle Scenario with what the monitors witnessed in place of the "
                                           "vehicle's own view,",
             "monitor scenario": "what its spawn and the monitors recorded",
             "spawn only": "its spawn only"}
LAWFUL = {True: "yes", False: "NO", None: "not decided"}


def scene_lines(sc: Scene) -> list[str]:
    """The whole scene: header, rulebooks, signals, monitors, then each vehicle."""
    last = sc.last
    lines = [f"Run {sc.run} at {sc.t_iso} ({sc.offset} from the run start, {sc.run_start_iso})",
             f"{sc.events} events up to then" + (f"; the last: {last.src} #{last.seq}" if last else "")]
    if sc.note:
        lines.append(f"Note: {sc.note}")
    books = ", ".join(f"{b.name} ({str(b.sha256)[:12]}…)" for b in sc.rulebooks)
    lines += [f"Rulebooks recorded: {books or 'none'}", ""]
    lines += _signals(sc) + _monitors(sc)
    if not sc.vehicles:
        lines += ["", "No vehicle present at this time."]
    for v in sc.vehicles:
        lines += [""] + vehicle_lines(sc, v)
    return lines


def vehicle_lines(sc: Scene, v: VehicleShown) -> list[str]:
    """One vehicle: where, who was in control, its scenarios and action, and whether it was lawful."""
    lines = [f"Vehicle {v.vehicle} ({v.type or 'type not recorded'})"
             + ("" if v.recorded else ": known only from monitors' observations")]
    if (now := v.state) is not None:
        junction = f", in junction {now.field('junction')}" if now.field("junction") else ""
        road = f", road {now.field('road')}" if now.field("road") is not None else ""       # inside a junction: none
        lines.append(f"  at ({_num(now.field('x'))}, {_num(now.field('y'))}) m, "
                     f"speed {speed_text(now.field('speed_mps'))}{road}{junction} ({_cite(now.evidence, sc)})")
    lines.append(f"  in control: {_control(sc, v.control)}")
    lines += _facts("Vehicle Scenario", v.vehicle_scenario, sc)
    lines.append(_action(sc, v.vehicle_action))
    if not v.monitor_scenarios:
        lines.append("  Monitor Scenarios: no monitor has observed it")
    for m in v.monitor_scenarios:
        lines += _facts(f"Monitor Scenario of {m.monitor}", m.facts, sc)
    return lines + _validator(sc, v.validator_scenario)


def _signals(sc: Scene) -> list[str]:
    lines = ["Signals" + ("" if sc.signals else ": none reported yet")]
    for s in sc.signals:
        lines.append(f"  {s.junction} {s.approach}: {SIGNAL_WORDS.get(s.colour, s.colour)} since {format_time(s.since.t)} "
                     f"({_offset(sc, s.since.t)}, {_cite(s.since)})")
    return lines


def _monitors(sc: Scene) -> list[str]:
    lines = ["Monitors" + ("" if sc.monitors else ": none")]
    for m in sc.monitors:
        place = (f" at junction {m.placed('junction')}, ({_num(m.placed('x'))}, {_num(m.placed('y'))}) m, "
                 f"range {_num(m.placed('range_m'))} m" if m.entry else " (not on the run's map)")
        observed = ", ".join(str(v) for v in m.observed) or "nothing yet"
        lines.append(f"  {m.monitor}{place}; observed: {observed}")
        for pv in m.potential_violations:
            lines.append(f"    potential violation: {pv.vehicle} {pv.action} ({_cite(pv.evidence)})")
    return lines


def _action(sc: Scene, action: Decision | None) -> str:
    if action is None:
        return "  Vehicle Action: none recorded"
    return (f"  Vehicle Action: goal \"{action.goal}\", action \"{action.action}\", "
            f"permitted: {_yes(action.permitted)}, proceeds: {_yes(action.proceeds)} "
            f"({_cite(action.evidence, sc)})")


def _validator(sc: Scene, val: ValidatorShown) -> list[str]:
    goal = f"with the goal \"{val.goal}\"" if val.goal else "without a goal (no decision recorded)"
    lines = [f"  Validator Scenario: {JUDGED_ON[val.judged_on]} {goal}"]
    if val.judged_on != "vehicle scenario":
        lines += _facts("", val.facts, sc)
    if (judged := val.judged) is not None:         # judged only when asked (--judge, or one --vehicle)
        book = judged.rulebook
        by = f" ({book.name}, {book.source}, {str(book.sha256)[:12]}…)" if book else ""
        lines.append(f"  lawful: {LAWFUL[judged.lawful]}{by}: {judged.why}")
        if judged.own_view_asked:
            lines.append(f"    on the vehicle's own view alone it would be {LAWFUL[judged.lawful_on_its_own_view]}; "
                         "what the monitors witnessed decides, as in the incident")
        lines += [f"    unknown fact, not used: {u.fact}" for u in judged.unknown_facts]
    return lines


def _facts(title: str, facts: tuple[SceneFact, ...], sc: Scene) -> list[str]:
    lines = [f"  {title}:" + ("" if facts else " no facts")] if title else []
    width = max((len(str(f.fact)) for f in facts), default=0)
    for f in facts:
        ev = f.evidence
        cited = f"{ev.kind} {_cite(ev, sc)}" if ev is not None else "(no event)"
        lines.append(f"    {str(f.fact).ljust(width)}  {cited}")
    return lines


def _control(sc: Scene, c: Control) -> str:
    text = c.in_control
    if c.engaged and c.since:
        text += f" (engaged since {_offset(sc, c.since.t)}, {_cite(c.since)})"
    elif c.automated:
        text += " (the self-driving feature is not engaged)"
    if demand := c.transition_demand:
        state = "expired unanswered" if c.transition_demand_expired else "pending"
        text += f"; transition demand at {_offset(sc, demand.t)} {state} ({_cite(demand)})"
    if c.minimal_risk_manoeuvre:
        text += "; minimal risk manoeuvre in progress"
    return text


def _cite(ref: EventRef | Cited, sc: Scene | None = None) -> str:
    """Where a fact was recorded: an EventRef, or the fold's citation of a piece of state."""
    where = f"{ref.src} #{ref.seq}"
    return f"{where}, {_offset(sc, ref.t)}" if sc is not None else where


def _offset(sc: Scene | None, t: int) -> str:
    return format_offset(t - sc.run_start) if sc else str(t)


def _yes(value: Any) -> str:
    if isinstance(value, bool) or value is None:
        return {True: "yes", False: "no", None: "not recorded"}[value]
    return str(value)


def _num(value: Any) -> str:
    return str(value) if value is not None else "?"
