"""The paper's two junction scenarios (section 7.2) as a recorded run of DESIGN's events.

Car 173 and ambulance 253 (on an emergency call) each reach a red light at junction j1 and
enter it; monitor m1 watches the junction.  The vehicles' `permitted` answers are not written
in: each vehicle asks the rulebook on its own perception, as a vehicle in the simulation would.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from reasoner.onboard import PAPER, bundled, get_engine, parse_fact, sha256_text
from reasoner.vocabulary import CAN, HAS_LIGHT, IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL

RUN = "paper-junctions"
T0 = 1_732_176_000_000_000_000          # 2024-11-21T08:00:00Z, fixed so the demo is reproducible
SECOND = 1_000_000_000
ACTION = "enter the junction"

MAP = {
    "roads": [{"id": "r1", "from": [-200.0, 0.0], "to": [200.0, 0.0]},
              {"id": "r2", "from": [0.0, -200.0], "to": [0.0, 200.0]}],
    "junctions": [{"id": "j1", "x": 0.0, "y": 0.0, "control": "lights",
                   "stop_lines": [{"approach": "west", "from": [-12.0, -3.5], "to": [-12.0, 3.5], "kind": "signal"}]}],
    "monitors": [{"id": "m1", "junction": "j1", "x": -15.0, "y": 10.0, "heading_deg": 0.0,
                  "range_m": 60.0, "fov_deg": 90.0}],
}


@dataclass
class Recorder:
    """Numbers each source's events from 0, as every producer must."""

    run: str
    events: list[dict] = field(default_factory=list)
    seqs: dict[str, int] = field(default_factory=dict)

    def emit(self, src: str, t: int, kind: str, body: dict) -> dict:
        seq = self.seqs.get(src, 0)
        self.seqs[src] = seq + 1
        event = {"v": 1, "run": self.run, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}
        self.events.append(event)
        return event


@dataclass
class Crossing:
    """One vehicle reaching j1 on red and entering the junction."""

    vehicle: str
    type: str
    emergency: bool
    arrives_s: float


CROSSINGS = [Crossing("173", "car", False, 10.0), Crossing("253", "ambulance", True, 40.0)]


def paper_run(run: str = RUN) -> list[dict]:
    """Every event of the demo run, in publication order."""
    text = bundled(PAPER)
    rb = get_engine().load(text, PAPER)
    rec = Recorder(run)
    rec.emit("sim/world", T0, "run.start", {
        "map": MAP, "seed": 0, "config": {"scenario": "Mind the Gaps, section 7.2"},
        "rulebooks": [{"name": PAPER, "sha256": sha256_text(text), "text": text}]})
    for c in CROSSINGS:
        rec.emit(f"vehicle/{c.vehicle}", T0, "entity.spawn", {
            "type": c.type, "driver": "human", "automation_level": 0, "emergency": c.emergency,
            "plate": f"GAPS {c.vehicle}"})
    for c in CROSSINGS:
        _signal_cycle(rec, c)
        _crossing(rec, rb, c)
    rec.emit("sim/world", T0 + 60 * SECOND, "run.end", {"reason": "scenario complete"})
    return rec.events


def _signal_cycle(rec: Recorder, c: Crossing) -> None:
    t = T0 + int((c.arrives_s - 6) * SECOND)
    rec.emit("signal/j1-west", t, "signal.state", {"junction": "j1", "approach": "west", "colour": "amber"})
    rec.emit("signal/j1-west", t + 3 * SECOND, "signal.state",
             {"junction": "j1", "approach": "west", "colour": "red"})


def _crossing(rec: Recorder, rb, c: Crossing) -> None:
    v, src = c.vehicle, f"vehicle/{c.vehicle}"
    t = T0 + int(c.arrives_s * SECOND)
    facts = [IS_OF_TYPE.text(v, c.type), HAS_LIGHT.text(v, "red")]
    if c.emergency:
        facts.append(IS_ON_AN_EMERGENCY_CALL.text(v))
    rec.emit(src, t - SECOND, "entity.state",
             {"x": -20.0, "y": 0.0, "heading_deg": 0.0, "speed_mps": 9.0, "road": "r1", "junction": None})
    rec.emit(src, t - SECOND // 2, "vehicle.perception", {"facts": facts})
    goal = CAN.text(v, ACTION)
    rec.emit(src, t - SECOND // 2, "vehicle.decision", {
        "goal": goal, "action": ACTION, "permitted": _permitted(rb, goal, facts), "proceeds": True,
        "rulebook": rb.sha256})
    rec.emit(src, t, "entity.state",
             {"x": -2.0, "y": 0.0, "heading_deg": 0.0, "speed_mps": 9.0, "road": "r1", "junction": "j1"})
    seen = [HAS_LIGHT.text(v, "red")]
    rec.emit("monitor/m1", t, "monitor.observation",
             {"vehicle": v, "facts": seen, "speed_mps": 9.0, "x": -2.0, "y": 0.0})
    rec.emit("monitor/m1", t, "monitor.potential_violation",
             {"vehicle": v, "action": ACTION, "facts": seen, "rulebook": rb.sha256})


def _permitted(rb, goal: str, facts: list[str]) -> bool:
    """Ask the rulebook, on the vehicle's own perception, whether its goal is permitted."""
    templates = rb.document.templates
    atoms = [a for f in facts if (a := parse_fact(f, templates))]
    asked = parse_fact(goal, templates)
    assert asked is not None        # the goal is the vocabulary's own sentence
    return get_engine().ask(rb, asked, atoms).holds
