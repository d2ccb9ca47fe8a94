"""What a simulation run is asked to be: the map, the mix of road users, their behaviour, the faults.

A `SimConfig` is everything that decides a run besides the code: the same config (seed included)
gives the same events, byte for byte apart from wall-clock fields (there are none in the events).
It travels in run.start's `config`, so a recording says how it was made. Rates are per chance
(per junction passage, per event, per vehicle) so that a short run can raise them until the acts a
test needs occur, and a long run keeps them low.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

__all__ = ["Behaviour", "FaultRates", "SimConfig"]


@dataclass(frozen=True)
class Behaviour:
    """Human drivers' profiles: the share of drivers with each habit, and how often one with the
    habit acts on it at a chance (a junction passage where it can). A driver may have none."""

    speeder: float = 0.08          # drives at `speeding_factor` times the limit
    amber_runner: float = 0.10     # goes on at amber although it could stop
    red_runner: float = 0.03       # goes on at red
    stop_roller: float = 0.15      # rolls over a Stop line at walking pace instead of stopping
    no_give_way: float = 0.15      # pulls out of a Give Way line into approaching traffic
    propensity: float = 0.7        # chance a driver with a habit acts on it at a passage
    recorder: float = 0.2          # share of human drivers whose car records perception and decisions
    speeding_factor: tuple[float, float] = (1.2, 1.45)
    reaction_s: tuple[float, float] = (0.5, 1.5)


@dataclass(frozen=True)
class FaultRates:
    """Injected faults, each with its own seeded stream; 0 turns one off."""

    misperceived_light: float = 0.0   # per automated passage of a signal line: the ADS sees the wrong colour
    missed_road_user: float = 0.0     # per road user an automated vehicle should perceive: it does not
    speed_error: float = 0.0          # per monitor and vehicle sighting: the camera's speed reads high
    lost_event: float = 0.0           # per event of LOSSY_KINDS: published with a seq, never delivered
    recorder_stops: float = 0.0       # per recording vehicle: its recorder stops publishing mid-run


LOSSY_KINDS = ("entity.state", "monitor.observation", "vehicle.perception")


@dataclass(frozen=True)
class SimConfig:
    """One simulation run. `map` names a bundled map (sim_replay.maps); `net` and `monitors`
    (paths) replace it with any SUMO network and monitors file (none: no cameras; `gaps sim`
    then writes the network's file name in `map`, for a reader of the config); `routes`
    (paths of .rou.xml files) replace the drawn vehicles and pedestrians with the files'."""

    run: str = "sim-001"
    seed: int = 0
    map: str = "paper"
    net: str | None = None
    monitors: str | None = None
    routes: tuple[str, ...] = ()
    vehicles: int = 40
    duration_s: float = 180.0
    rate_hz: float = 10.0              # entity.state and monitor.observation per road user per second
    av_share: float = 0.3              # share of cars driven by an automated driving system
    emergency_share: float = 0.08      # ambulances, fire engines, police cars (marked and unmarked)
    on_call_share: float = 0.6         # share of emergency vehicles on a call when they set off
    call_change_per_min: float = 0.5   # rate at which an emergency vehicle goes on or off a call
    bus_share: float = 0.05
    cyclist_share: float = 0.05
    pedestrians: int = 12
    ads_event_per_min: float = 0.3     # rate of transition demands per engaged automated vehicle
    depart_within: float = 0.7         # vehicles set off over this share of the run
    decide_m: float = 50.0             # a vehicle starts deciding this far before its stop line
    behaviour: Behaviour = field(default_factory=Behaviour)
    faults: FaultRates = field(default_factory=FaultRates)

    @property
    def step_every(self) -> int:
        """Publish every this many 0.1 s world steps (rate_hz 10: every step)."""
        return max(1, round(10.0 / self.rate_hz))

    def to_json(self) -> dict[str, Any]:
        out = asdict(self)
        out["routes"] = list(self.routes)
        out["behaviour"]["speeding_factor"] = list(self.behaviour.speeding_factor)
        out["behaviour"]["reaction_s"] = list(self.behaviour.reaction_s)
        return out
