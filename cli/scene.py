"""`gaps scene --run R --at T`: what the record says was going on at one moment.

The scene itself is reasoner/scene.py's; the time forms are reasoner/when.py's. This module
parses the options and prints, with every producer-written string escaped (cli/safe_text.py).
Exit codes: 0 shown; 2 for what was asked naming nothing (no store, no such run, a time that
cannot be read, a vehicle not present at that time), like every other `gaps` usage error.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import DbOption, JsonOption, app, fail, open_existing, print_json
from cli.safe_text import printable

AT_HELP = ("When: ns since the epoch (1732176010000000000), seconds from the run start (12.5s, 1m30s) "
           "or ISO 8601 with a zone (2024-11-21T08:00:10.25Z).")


@app.command("scene")
def scene_command(run: str = typer.Option(..., "--run", help="Run id."),
                  at: str = typer.Option(..., "--at", help=AT_HELP),
                  vehicle: Optional[str] = typer.Option(None, "--vehicle", help="Only this vehicle (its id, e.g. 173)."),
                  judge: Optional[bool] = typer.Option(
                      None, "--judge/--no-judge",
                      help="Ask the validator rulebook whether each goal is lawful (default: with --vehicle)."),
                  db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """The scene at a time: signals, monitors, and per vehicle its position, who was in control, and
    the Vehicle, Monitor and Validator Scenarios and Vehicle Action, each fact with its event."""
    from reasoner.scene import SceneError, run_start, scene
    from reasoner.when import TimeError, parse_time
    with open_existing(db) as store:
        try:
            t = parse_time(at, run_start(store, run))
            found = scene(store, run, t, vehicle=vehicle, judge=judge)
        except (SceneError, TimeError) as exc:
            fail(str(exc))
    if json_out:
        print_json(found)
    else:
        _print_scene(found)


# --- text -------------------------------------------------------------------------------------

def _print_scene(sc: dict[str, Any]) -> None:
    from reasoner.when import format_time
    say = typer.echo
    say(f"Run {_s(sc['run'])} at {sc['t_iso']} ({sc['offset']} from the run start, {sc['run_start_iso']})")
    last = sc["last"]
    say(f"{sc['events']} events up to then" + (f"; the last: {_s(last['src'])} #{last['seq']}" if last else ""))
    if sc["note"]:
        say(f"Note: {sc['note']}")
    books = ", ".join(f"{_s(b.get('name'))} ({_s(b.get('sha256'))[:12]}…)" for b in sc["rulebooks"])
    say(f"Rulebooks recorded: {books or 'none'}")
    say("")
    say("Signals" + ("" if sc["signals"] else ": none reported yet"))
    for s in sc["signals"]:
        say(f"  {_s(s['junction'])} {_s(s['approach'])}: {_s(s['colour'])} since {format_time(s['since']['t'])} "
            f"({_offset(sc, s['since']['t'])}, {_cite(s['since'])})")
    say("Monitors" + ("" if sc["monitors"] else ": none"))
    for m in sc["monitors"]:
        where = m["map"] or {}
        place = (f" at junction {_s(where.get('junction'))}, ({_num(where.get('x'))}, {_num(where.get('y'))}) m, "
                 f"range {_num(where.get('range_m'))} m" if where else " (not on the run's map)")
        observed = ", ".join(_s(v) for v in m["observed"]) or "nothing yet"
        say(f"  {_s(m['monitor'])}{place}; observed: {observed}")
        for pv in m["potential_violations"]:
            say(f"    potential violation: {_s(pv['vehicle'])} {_s(pv['action'])} ({_cite(pv['evidence'])})")
    if not sc["vehicles"]:
        say("\nNo vehicle present at this time.")
    for v in sc["vehicles"]:
        say("")
        _print_vehicle(sc, v)


def _print_vehicle(sc: dict[str, Any], v: dict[str, Any]) -> None:
    say = typer.echo
    say(f"Vehicle {_s(v['vehicle'])} ({_s(v['type'] or 'type not recorded')})"
        + ("" if v["recorded"] else ": known only from monitors' observations"))
    if (now := v["state"]) is not None:
        junction = f", in junction {_s(now['junction'])}" if now.get("junction") else ""
        say(f"  at ({_num(now.get('x'))}, {_num(now.get('y'))}) m, speed {_num(now.get('speed_mps'))} m/s, "
            f"road {_s(now.get('road'))}{junction} ({_cite(now['evidence'], sc)})")
    say(f"  in control: {_control(sc, v['control'])}")
    _print_facts("Vehicle Scenario", v["vehicle_scenario"], sc)
    action = v["vehicle_action"]
    if action is None:
        say("  Vehicle Action: none recorded")
    else:
        say(f"  Vehicle Action: goal \"{_s(action['goal'])}\", action \"{_s(action['action'])}\", "
            f"permitted: {_yes(action['permitted'])}, proceeds: {_yes(action['proceeds'])} "
            f"({_cite(action['evidence'], sc)})")
    if not v["monitor_scenarios"]:
        say("  Monitor Scenarios: no monitor has observed it")
    for m in v["monitor_scenarios"]:
        _print_facts(f"Monitor Scenario of {_s(m['monitor'])}", m["facts"], sc)
    val = v["validator_scenario"]
    on = {"vehicle scenario": "the Vehicle Scenario", "monitor scenario": "what its spawn and the monitors recorded",
          "spawn only": "its spawn only"}[val["judged_on"]]
    goal = f"with the goal \"{_s(val['goal'])}\"" if val["goal"] else "without a goal (no decision recorded)"
    say(f"  Validator Scenario: {on} {goal}")
    if val["judged_on"] != "vehicle scenario":
        _print_facts("", val["facts"], sc)
    if "lawful" in val:
        book = val["rulebook"]
        by = f" ({_s(book['name'])}, {book['source']}, {_s(book['sha256'])[:12]}…)" if book else ""
        verdict = {True: "yes", False: "NO", None: "not decided"}[val["lawful"]]
        say(f"  lawful: {verdict}{by}: {_s(val['why'])}")
        for u in val["unknown_facts"]:
            say(f"    unknown fact, not used: {_s(u['fact'])}")


def _print_facts(title: str, facts: list[dict], sc: dict[str, Any]) -> None:
    if title:
        typer.echo(f"  {title}:" + ("" if facts else " no facts"))
    width = max((len(_s(f["fact"])) for f in facts), default=0)
    for f in facts:
        ev = f["evidence"]
        typer.echo(f"    {_s(f['fact']).ljust(width)}  {ev['kind']} {_cite(ev, sc)}")


def _control(sc: dict[str, Any], c: dict[str, Any]) -> str:
    text = c["in_control"]
    if c["engaged"] and c["since"]:
        text += f" (engaged since {_offset(sc, c['since']['t'])}, {_cite(c['since'])})"
    elif c["automated"]:
        text += " (the self-driving feature is not engaged)"
    if demand := c["transition_demand"]:
        state = "expired unanswered" if c["transition_demand_expired"] else "pending"
        text += f"; transition demand at {_offset(sc, demand['t'])} {state} ({_cite(demand)})"
    if c["minimal_risk_manoeuvre"]:
        text += "; minimal risk manoeuvre in progress"
    return text


def _cite(ref: dict[str, Any], sc: dict[str, Any] | None = None) -> str:
    where = f"{_s(ref['src'])} #{ref['seq']}"
    return f"{where}, {_offset(sc, ref['t'])}" if sc is not None else where


def _offset(sc: dict[str, Any] | None, t: int) -> str:
    from reasoner.when import format_offset
    return format_offset(t - sc["run_start"]) if sc else str(t)


def _yes(value: Any) -> str:
    return {True: "yes", False: "no", None: "not recorded"}.get(value, _s(value)) if isinstance(
        value, (bool, type(None))) else _s(value)


def _num(value: Any) -> str:
    return _s(value) if value is not None else "?"


def _s(value: Any) -> str:
    return printable(str(value))
