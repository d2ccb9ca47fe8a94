"""A small builder of recorded runs for the verdict-path tests.

A run is what DESIGN's producers publish: a `run.start` with the map and the rulebooks in force
(name, sha256 and full LE text), spawns, ads.events, signal states, the vehicles' perceptions and
decisions, the monitors' observations and potential violations, each source numbered from seq 0.
The builder writes no verdict: a vehicle's `permitted` is what its own rulebook (highway_code.le,
recorded in the run) answers on its own perception, unless a test states another answer on purpose
(a decision fault).

    run = RunBuilder()
    run.spawn("173")
    run.crossing("173", at=10, perceived=["173 is of type car", "173 has red light"],
                 observed=["173 has red light"])
    events = run.finish()
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from pathlib import Path

from reasoner.bundled import bundled
from reasoner.engine import get_engine, sha256_text
from reasoner.le.sentences import parse_fact
from store import Store

RUN = "verdict-paths"
T0 = 1_732_176_000_000_000_000          # 2024-11-21T08:00:00Z
SECOND = 1_000_000_000
ENTER = "enter the junction"
SPEEDING = "exceed the speed limit"

# The rulebooks a run records, by the role each plays (reasoner/rules/README.md).
BOOKS = ("highway_code.le", "monitors.le", "validators.le", "penalties.le", "liability.le")
VEHICLE_BOOK = "highway_code.le"        # what a vehicle asks before it acts
MONITOR_BOOK = "monitors.le"            # what a monitor records potential violations with

MAP = {
    "roads": [{"id": "r1", "from": [-200.0, 0.0], "to": [200.0, 0.0]},
              {"id": "r2", "from": [0.0, -200.0], "to": [0.0, 200.0]},
              {"id": "r3", "from": [400.0, -200.0], "to": [400.0, 200.0]}],
    "junctions": [{"id": "j1", "x": 0.0, "y": 0.0, "control": "lights"},
                  {"id": "j2", "x": 200.0, "y": 0.0, "control": "stop"}],
    "monitors": [{"id": "m1", "junction": "j1", "x": -15.0, "y": 10.0, "heading_deg": 0.0,
                  "range_m": 60.0, "fov_deg": 90.0},
                 {"id": "m2", "junction": "j2", "x": 185.0, "y": 10.0, "heading_deg": 0.0,
                  "range_m": 60.0, "fov_deg": 90.0}],
}
JUNCTION_X = {"j1": 0.0, "j2": 200.0}
MONITOR_OF = {"j1": "m1", "j2": "m2"}


def car(v: str) -> list[str]:
    """What a car's perception says it is."""
    return [f"{v} is of type car"]


def ns(seconds: float) -> int:
    """World time of a moment given in seconds from the run's start."""
    return T0 + round(seconds * SECOND)


def recorded_rulebook(name: str, text: str | None = None) -> dict:
    """A run.start rulebook entry: name, sha256 of the UTF-8 text, and the text."""
    text = bundled(name) if text is None else text
    return {"name": name, "sha256": sha256_text(text), "text": text}


def permitted(goal: str, facts: list[str], book: str = VEHICLE_BOOK) -> bool:
    """What the vehicle's rulebook answers to its goal on its perception (unknown sentences are
    left out, as a vehicle's parser would)."""
    rb = get_engine().load(bundled(book), book)
    templates = rb.document.templates
    atoms = [a for f in facts if (a := _parse(f, templates)) is not None]
    return get_engine().ask(rb, parse_fact(goal, templates), atoms).holds


def _parse(sentence: str, templates):
    try:
        return parse_fact(sentence.strip().rstrip("."), templates)
    except Exception:       # a hostile sentence: the vehicle ignores it
        return None


@dataclass
class RunBuilder:
    """Events of one run in publication order; every source is numbered from seq 0."""

    run: str = RUN
    books: tuple[str, ...] | None = BOOKS       # None: the run records no rulebook
    map: dict = field(default_factory=lambda: copy.deepcopy(MAP))
    events: list[dict] = field(default_factory=list)
    seqs: dict[str, int] = field(default_factory=dict)
    started: bool = False

    # -- the envelope ------------------------------------------------------------------------
    def emit(self, src: str, t: int, kind: str, body: dict) -> dict:
        if not self.started:
            self.start()
        seq = self.seqs.get(src, 0)
        self.seqs[src] = seq + 1
        event = {"v": 1, "run": self.run, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}
        self.events.append(event)
        return event

    def start(self) -> dict:
        self.started = True
        body = {"map": self.map, "seed": 0, "config": {"scenario": "tests/reasoner/test_verdict_paths.py"}}
        if self.books is not None:
            body["rulebooks"] = [recorded_rulebook(b) for b in self.books]
        return self.emit("sim/world", T0, "run.start", body)

    def finish(self, at: float = 120.0) -> list[dict]:
        self.emit("sim/world", ns(at), "run.end", {"reason": "scenario complete"})
        return self.events

    def sha(self, book: str) -> str | None:
        return sha256_text(bundled(book)) if self.books is not None and book in self.books else None

    # -- what each kind of producer publishes -------------------------------------------------
    def spawn(self, vehicle: str, type: str = "car", *, driver: str = "human", automation_level: int = 0,
              emergency: bool = False, at: float = 0.0) -> dict:
        return self.emit(f"vehicle/{vehicle}", ns(at), "entity.spawn", {
            "type": type, "driver": driver, "automation_level": automation_level, "emergency": emergency,
            "plate": f"GAPS {vehicle}"})

    def ads(self, vehicle: str, event: str, at: float, reason: str | None = None) -> dict:
        body = {"event": event, "software": {"ads": "4.2.0"}}
        if reason:
            body["reason"] = reason
        return self.emit(f"vehicle/{vehicle}", ns(at), "ads.event", body)

    def signal(self, colour: str, at: float, junction: str = "j1", approach: str = "west") -> dict:
        return self.emit(f"signal/{junction}-{approach}", ns(at), "signal.state",
                         {"junction": junction, "approach": approach, "colour": colour})

    def state(self, vehicle: str, at: float, x: float, speed_mps: float, junction: str | None = None) -> dict:
        return self.emit(f"vehicle/{vehicle}", ns(at), "entity.state", {
            "x": x, "y": 0.0, "heading_deg": 0.0, "speed_mps": speed_mps, "road": "r1", "junction": junction})

    def perceive(self, vehicle: str, at: float, facts: list[str]) -> dict:
        return self.emit(f"vehicle/{vehicle}", ns(at), "vehicle.perception", {"facts": list(facts)})

    def decide(self, vehicle: str, at: float, facts: list[str], action: str = ENTER, *,
               says: bool | None = None, proceeds: bool = True) -> dict:
        """The vehicle's decision; `permitted` is its rulebook's answer on `facts` unless `says`
        states another (a decision fault)."""
        goal = f"{vehicle} can {action}"
        answer = permitted(goal, facts) if says is None else says
        body = {"goal": goal, "action": action, "permitted": answer, "proceeds": proceeds}
        if sha := self.sha(VEHICLE_BOOK):
            body["rulebook"] = sha
        return self.emit(f"vehicle/{vehicle}", ns(at), "vehicle.decision", body)

    def observe(self, vehicle: str, at: float, facts: list[str], monitor: str = "m1", *,
                speed_mps: float | None = None, x: float | None = None) -> dict:
        """A monitor's observation: its sentences, and its measurements only where given."""
        body: dict = {"vehicle": vehicle, "facts": list(facts)}
        if speed_mps is not None:
            body["speed_mps"] = speed_mps
        if x is not None:
            body.update(x=x, y=0.0)
        return self.emit(f"monitor/{monitor}", ns(at), "monitor.observation", body)

    def potential_violation(self, vehicle: str, at: float, action: str, facts: list[str],
                            monitor: str = "m1") -> dict:
        body = {"vehicle": vehicle, "action": action, "facts": list(facts)}
        if sha := self.sha(MONITOR_BOOK):
            body["rulebook"] = sha
        return self.emit(f"monitor/{monitor}", ns(at), "monitor.potential_violation", body)

    # -- one vehicle reaching a junction --------------------------------------------------------
    def crossing(self, vehicle: str, at: float, perceived: list[str], observed: list[str], *,
                 action: str = ENTER, goal: str | None = None, junction: str = "j1",
                 says: bool | None = None, proceeds: bool = True, record: bool = True,
                 speed_mps: float = 9.0, observations: int = 1) -> dict:
        """The vehicle approaches, perceives, decides, moves (or stays), is observed by the
        junction's monitor `observations` times (0.2 s apart, the last at `at`) and, if `record`,
        the monitor records a potential violation of `action` at `at`. The decision's goal is
        `goal` (default: `action`). Returns the events by role."""
        x0 = JUNCTION_X[junction]
        moving = speed_mps if proceeds else 0.0
        monitor = MONITOR_OF[junction]
        out: dict = {}
        out["approach"] = self.state(vehicle, at - 1.0, x0 - 20.0, speed_mps)
        out["perception"] = self.perceive(vehicle, at - 0.5, perceived)
        out["decision"] = self.decide(vehicle, at - 0.5, perceived, goal or action,
                                      says=says, proceeds=proceeds)
        inside = junction if proceeds else None
        out["state"] = self.state(vehicle, at, x0 - 2.0 if proceeds else x0 - 15.0, moving, inside)
        out["observations"] = [
            self.observe(vehicle, at - 0.2 * (observations - 1 - i), observed, monitor,
                         speed_mps=moving, x=x0 - 2.0 if proceeds else x0 - 15.0)
            for i in range(observations)]
        out["observation"] = out["observations"][0]
        if record:
            out["pv"] = self.potential_violation(vehicle, at, action, observed, monitor)
        out["after"] = self.state(vehicle, at + 1.0, x0 + 7.0 if proceeds else x0 - 15.0, moving,
                                  junction if proceeds else None)
        return out

    def lights(self, at: float, colour: str, junction: str = "j1") -> None:
        """The signal cycle that shows `colour` at `at` (green, then amber, then red)."""
        if colour == "green":
            self.signal("green", at - 4.0, junction)
        elif colour == "amber":
            self.signal("green", at - 8.0, junction)
            self.signal("amber", at - 1.5, junction)
        elif colour == "red":
            self.signal("green", at - 12.0, junction)
            self.signal("amber", at - 6.0, junction)
            self.signal("red", at - 3.0, junction)
        else:
            raise ValueError(colour)


def incidents(path: Path, events: list[dict], run: str = RUN, *, batches: int | None = None,
              rules: list | None = None) -> list[dict]:
    """Append `events` to a new store at `path` (in `batches` of that many, or all at once) and
    return the run's incidents."""
    from reasoner.investigation import Investigation

    with Store(path) as store:
        size = batches or max(len(events), 1)
        for i in range(0, len(events), size):
            report = store.append(events[i:i + size])
            assert not report.rejected, report.rejected
        inv = Investigation(store) if rules is None else Investigation(store, rules=rules)
        return inv.incidents(run)
