"""The ground truth of a simulated run: what the simulation made happen, never what a verdict should be.

The store is evidence; the truth is a test oracle, written beside a recording and never into the
store (DESIGN "Simulation"). It holds:

    road_users  who took part: type, driver, automation level, behaviour profile, recorder
    acts        each stop line crossed (who, which line, when, on what light, at what speed,
                whether it had stopped at it, whether on an emergency call, what was approaching)
                and each stretch over the speed limit; with why: the profile, the decision (the
                rulebook's answer where the vehicle asked it), the fault
    faults      each injected fault: when, to whom, what was wrong
    yields      SUMO's own account (sim_replay/sumo_account.py, when the simulation keeps it): each
                stretch of braking near a junction, with the cause SUMO's car-following model
                gives for it (a junction foe, a leader, its own signal or line, its turn, a
                pedestrian on a crossing) and how hard it braked under each
    conflicts   SUMO's SSM device: each conflict of two vehicles (ego, foe) with its TTC, DRAC and
                PET; and on each crossing, `sumo`: who SUMO says braked for it and the
                pedestrians on a crossing of its path while it passed

No rule of the Highway Code is restated here: an act says "crossed the west line of j1 on red",
and tests turn acts into expected verdicts with a table of their own.
"""
from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Iterable

from sim_replay.sumo_account import COMING_S
from store import write_text

__all__ = ["ABOUT_S", "Act", "EXIT_M", "InjectedFault", "REACTION_S", "Truth", "yielded_to"]

EXIT_M = 20.0                        # a road user standing this close beyond the junction blocks its exit
REACTION_S = 5.0                     # how long after an act the road users about it are watched braking
ABOUT_S = (3.0, 8.0)                 # SUMO's yields for a crossing: braking begun this long before it (the
                                     # vehicle setting off from its line) until this long after (through)


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
    in_path: tuple[tuple[str, str, float | None, float], ...] = ()   # pedestrians in its path over a crossing
                                     # within crossing_paths.WINDOW_S of it: (who, crossing, nearest m, PET s)

    def to_json(self) -> dict[str, Any]:
        out = asdict(self)
        out["approaching"] = list(self.approaching)
        out["seen_by"] = list(self.seen_by)
        out["exit_queue"] = list(self.exit_queue)
        out["reactions"] = {who: decel for who, decel in self.reactions}
        out["in_path"] = [list(p) for p in self.in_path]
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
        self.yields: list[dict[str, Any]] | None = None       # SUMO's account, where the run kept it
        self.conflicts: list[dict[str, Any]] | None = None

    def road_user(self, ident: str, **about: Any) -> None:
        self.road_users.setdefault(ident, {}).update(about)

    def act(self, act: Act) -> None:
        self.acts.append(act)

    def fault(self, fault: InjectedFault) -> None:
        self.faults.append(fault)

    def account(self, yields: list[dict[str, Any]], conflicts: list[dict[str, Any]]) -> None:
        """SUMO's own account of the run (sim_replay.sumo_account), once it has ended."""
        self.yields, self.conflicts = yields, conflicts

    def to_json(self) -> dict[str, Any]:
        acts = sorted(self.acts, key=lambda a: (a.t_s, a.vehicle, a.kind))
        out: dict[str, Any] = {"run": self.run, "seed": self.seed, "config": self.config, "road_users": self.road_users,
               "acts": [a.to_json() for a in acts], "faults": [f.to_json() for f in self.faults]}
        if self.yields is not None and self.conflicts is not None:      # (SUMO's account gives both)
            out["yields"], out["conflicts"] = self.yields, self.conflicts
            for act in out["acts"]:
                if act["kind"] == "crossed the stop line":
                    act["sumo"] = {"yielded": yielded_to(act, self.yields, self.conflicts),
                                   "in_path": act["in_path"]}
        return out

    def write(self, path: str | Path, stores: Iterable[str | Path] = ()) -> Path:
        """The truth as JSON at `path`, never over evidence (store.write_text: not `stores`, nor
        any store this process opened, nor anything but a regular file)."""
        write_text(path, json.dumps(self.to_json(), indent=1, sort_keys=True) + "\n", stores)
        return Path(path)


def yielded_to(act: dict[str, Any], yields: list[dict[str, Any]],
               conflicts: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Who SUMO says braked for the act's vehicle V about its crossing: a stretch of braking begun
    within ABOUT_S of it with a cause naming V (V a junction foe it let pass or found in its path,
    or a leader that had joined its road ahead of it from another arm at the act's junction), how hard (its peak in a
    tick, and held over a second: sumo_account.HELD_S), from and down to what speed under that
    cause, and the SSM device's measures of the pair (ego the one braking, foe V) about then."""
    v, t = act["vehicle"], act["t_s"]
    out = []
    for y in yields:
        if y["vehicle"] == v or not t - ABOUT_S[0] <= y["t_s"] <= t + ABOUT_S[1]:
            continue
        for key, how in y["causes"].items():
            cause, _, by = key.partition(" ")
            if by != v or (cause == "leader" and not (how.get("merged")
                                                       and how.get("merged_at", act.get("junction")) == act.get("junction"))):
                continue                # a leader counts where it joined the road at this act's junction
            if cause == "foe" and how.get("foe_arrives_s", 0.0) > COMING_S:
                continue                # a foe it must let pass, still far off (SUMO lists one 480 m away)
            ssm = [c for c in conflicts if c["ego"] == y["vehicle"] and c["foe"] == v
                   and c["begin_s"] <= y["until_s"] + 1.0 and c["end_s"] >= y["t_s"] - 1.0]
            out.append({"vehicle": y["vehicle"], "t_s": how["t_s"], "cause": cause, "decel_mps2": how["decel_mps2"],
                        "held_mps2": how.get("held_mps2"), "road_user_held_mps2": how.get("road_user_held_mps2"),
                        "from_mps": how.get("from_mps"),
                        "speed_mps": y["speed_mps"], "min_speed_mps": how.get("min_speed_mps", y["min_speed_mps"]),
                        "ssm": {m: ssm[0][m] for m in ("minTTC", "maxDRAC", "PET") if ssm and m in ssm[0]}})
    return out
