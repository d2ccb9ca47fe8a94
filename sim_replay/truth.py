"""The ground truth of a simulated run: what the simulation made happen, never what a verdict should be.

The store is evidence; the truth is a test oracle, written beside a recording and never into the
store (DESIGN "Simulation"). It holds:

    road_users  who took part: type, driver, automation level, behaviour profile, recorder
    acts        each stop line crossed (who, which line, when, on what light, at what speed,
                whether it had stopped at it, whether on an emergency call, what was approaching)
                and each stretch over the speed limit; with why: the profile, the decision (the
                rulebook's answer where the vehicle asked it), the fault
    faults      each injected fault: when, to whom, what was wrong

No rule of the Highway Code is restated here: an act says "crossed the west line of j1 on red",
and tests turn acts into expected verdicts with a table of their own.
"""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Iterable

from store import write_text

__all__ = ["Act", "EXIT_M", "InjectedFault", "REACTION_S", "Truth"]

EXIT_M = 20.0                        # a road user standing this close beyond the junction blocks its exit
REACTION_S = 5.0                     # how long after an act the road users about it are watched braking


@dataclass(frozen=True)
class Act:
    """One thing a road user did that a law may be about."""

    kind: str                         # "crossed the stop line", "exceeded the speed limit", "stopped in the box"
    vehicle: str
    type: str
    driver: str                       # human, autonomous (engaged), user (took over from the ADS)
    t_s: float                        # world seconds (envelope t = sim_events.t_ns(t_s))
    until_s: float | None = None      # the end of a stretch (over the limit, standing in the box)
    junction: str | None = None
    approach: str | None = None
    line: str | None = None           # signal, stop, give_way
    light: str | None = None          # the colour facing its approach as its front crossed the line
    speed_mps: float = 0.0
    speed_mph: int = 0
    limit_mph: int | None = None
    stopped_at_line: bool = False     # stood still within a couple of metres of the line before crossing
    on_call: bool = False
    approaching: tuple[str, ...] = () # road users approaching as it crossed ("p3 pedestrian", "112 car main")
    reactions: tuple[tuple[str, float], ...] = ()   # each approaching vehicle's hardest braking (m/s²) in REACTION_S after,
                                                    # not counting braking for its own red or amber, or behind a leader
    exit_queue: tuple[str, ...] = ()  # standing in a box: who stood on its exit within EXIT_M of the junction
    at_amber: tuple[float, float] | None = None     # metres to the line and speed (m/s) when amber came, if it came
    turn: str | None = None           # left, straight, right: where it went from the line
    seen_by: tuple[str, ...] = ()     # monitors that had it in their cone at the act (or during the stretch)
    why: str = ""                     # profile, decision or fault that made it happen
    decision: dict[str, Any] | None = None   # the vehicle's last decision before the act, if it asked
    fault: str | None = None          # an injected fault at the root of it

    def to_json(self) -> dict[str, Any]:
        out = asdict(self)
        out["approaching"] = list(self.approaching)
        out["seen_by"] = list(self.seen_by)
        out["exit_queue"] = list(self.exit_queue)
        out["reactions"] = {who: decel for who, decel in self.reactions}
        return out


@dataclass(frozen=True)
class InjectedFault:
    kind: str                         # misperceived_light, missed_road_user, speed_error, lost_event, recorder_stops
    t_s: float
    src: str
    detail: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


class Truth:
    """Collected while the simulation runs; `to_json` / `write` when it has ended."""

    def __init__(self, run: str, seed: int, config: dict[str, Any]) -> None:
        self.run, self.seed, self.config = run, seed, config
        self.road_users: dict[str, dict[str, Any]] = {}
        self.acts: list[Act] = []
        self.faults: list[InjectedFault] = []

    def road_user(self, ident: str, **about: Any) -> None:
        self.road_users.setdefault(ident, {}).update(about)

    def act(self, act: Act) -> None:
        self.acts.append(act)

    def fault(self, fault: InjectedFault) -> None:
        self.faults.append(fault)

    def to_json(self) -> dict[str, Any]:
        acts = sorted(self.acts, key=lambda a: (a.t_s, a.vehicle, a.kind))
        return {"run": self.run, "seed": self.seed, "config": self.config, "road_users": self.road_users,
                "acts": [a.to_json() for a in acts], "faults": [f.to_json() for f in self.faults]}

    def write(self, path: str | Path, stores: Iterable[str | Path] = ()) -> Path:
        """The truth as JSON at `path`, never over evidence (store.write_text: not `stores`, nor
        any store this process opened, nor anything but a regular file)."""
        write_text(path, json.dumps(self.to_json(), indent=1, sort_keys=True) + "\n", stores)
        return Path(path)
