"""The kinds of road user the simulation puts on a SUMO network, as SUMO vehicle and person types.

A type's name is the word DESIGN's `entity.spawn` carries (car, ambulance, fire_engine, police_car,
bus, cyclist, pedestrian), so that what SUMO reports of a vehicle's type is already the event's
value. The figures are physics only: size, how fast it can go and how hard it can accelerate and
brake. How a driver behaves (speeding, running a red light) is the agents', set per vehicle; so every
type drives at exactly the speed limit here (`speedFactor` 1, no spread) and with SUMO's imperfection
(`sigma`, random dawdling) off, so that a vehicle's speed says what its agent chose.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["RoadUserType", "TYPES", "VEHICLE_KINDS", "PEDESTRIAN", "define_types"]

PEDESTRIAN = "pedestrian"


@dataclass(frozen=True)
class RoadUserType:
    """One kind of road user: its SUMO class and body. Lengths in metres, speeds m/s, rates m/s²."""

    name: str
    vclass: str           # SUMO's vehicle class: what lanes it may use and how SUMO treats it
    shape: str            # SUMO's drawing shape (sumo-gui), nothing else
    length_m: float
    width_m: float
    max_speed_mps: float
    accel_mps2: float
    decel_mps2: float     # the deceleration it plans with
    emergency_decel_mps2: float  # the hardest it can brake
    min_gap_m: float      # gap kept to the vehicle ahead when standing
    colour: tuple[int, int, int]


TYPES: dict[str, RoadUserType] = {t.name: t for t in (
    RoadUserType("car", "passenger", "passenger", 4.5, 1.8, 50.0, 2.6, 4.5, 9.0, 2.5, (200, 200, 200)),
    RoadUserType("ambulance", "emergency", "emergency", 6.5, 2.2, 45.0, 2.4, 4.5, 9.0, 2.5, (255, 230, 0)),
    RoadUserType("fire_engine", "emergency", "firebrigade", 8.5, 2.5, 36.0, 1.8, 4.0, 8.0, 2.5, (220, 0, 0)),
    RoadUserType("police_car", "authority", "police", 4.8, 1.9, 55.0, 3.0, 4.5, 9.0, 2.5, (40, 40, 220)),
    RoadUserType("bus", "bus", "bus", 12.0, 2.5, 25.0, 1.2, 4.0, 7.0, 2.5, (200, 0, 100)),
    RoadUserType("cyclist", "bicycle", "bicycle", 1.8, 0.65, 8.0, 1.2, 3.0, 7.0, 0.5, (0, 160, 0)),
    RoadUserType(PEDESTRIAN, "pedestrian", "pedestrian", 0.3, 0.5, 1.4, 1.5, 2.0, 5.0, 0.25, (0, 0, 0)),
)}
VEHICLE_KINDS = tuple(name for name in TYPES if name != PEDESTRIAN)


def define_types(sumo: Any) -> None:
    """Make every type in a running SUMO (the libsumo module), copied from SUMO's defaults and set.

    Types are made through the API rather than an additional file so that this table is the only
    place they are written; a copy of DEFAULT_VEHTYPE (or DEFAULT_PEDTYPE) keeps SUMO's car-following
    and lane-change models."""
    for t in TYPES.values():
        sumo.vehicletype.copy("DEFAULT_PEDTYPE" if t.name == PEDESTRIAN else "DEFAULT_VEHTYPE", t.name)
        vt = sumo.vehicletype
        vt.setVehicleClass(t.name, t.vclass)
        vt.setShapeClass(t.name, t.shape)
        vt.setLength(t.name, t.length_m)
        vt.setWidth(t.name, t.width_m)
        vt.setMaxSpeed(t.name, t.max_speed_mps)
        vt.setAccel(t.name, t.accel_mps2)
        vt.setDecel(t.name, t.decel_mps2)
        vt.setEmergencyDecel(t.name, t.emergency_decel_mps2)
        vt.setMinGap(t.name, t.min_gap_m)
        vt.setColor(t.name, (*t.colour, 255))
        if t.name != PEDESTRIAN:
            vt.setSpeedFactor(t.name, 1.0)
            vt.setSpeedDeviation(t.name, 0.0)
            vt.setImperfection(t.name, 0.0)
