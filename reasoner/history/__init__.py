"""What each road user did and what it believed, rebuilt from the record (DESIGN "Reasoning":
histories). This is the history's face: the rest of the reasoner, explain/ and sim_replay/ import
from here (`from reasoner.history import X`), never from a module inside.

    read            a vehicle's junction passages, read from a store or from events
    record          what a history is rebuilt from: one vehicle's measurements, map and signals
    rebuild         one vehicle's passages, rebuilt from a Record
    passage_values  a passage and its parts, as the record shows them
    junctions       the map as a history reads it
    motion          measured positions and speeds, and what is computed between them
    others          the other road users near a conflict point
    signals         what each signal showed and when
    state_samples   entity.state samples, read once per run and source
    sensors         the tolerance a producer states for its sensors
    scenarios       what a vehicle perceived and decided, and what a monitor saw, at a moment
    control         who was in control of a vehicle at a moment

It imports store and, of the reasoner, only its leaves (model, vocabulary, when).
"""
from .control import ROLE, control_at, liability_facts, role
from .junctions import UNIT, Junction, Map, read_map, sector
from .motion import (MAX_DECEL_MPS2, MIN_DECEL_SPAN_S, MPH_PER_MPS, STOPPED_MPS, Braking, Sample, between, mph,
                     peak_deceleration, position_at, sample_of, samples, speed_at, xy)
from .others import (FOLLOW_M, FOLLOW_S, MOVING_MPS, VEHICLE_WIDTH_M, braking_into, own_cause, paths_within, project,
                     since, through)
from .passage_values import AtChange, Other, Passage, Standstill
from .read import RunContext, from_events, passage, passage_at, passages, run_context, user_id, vehicle_src
from .rebuild import ANTICIPATION_S, LINE_EPS_M, PAST_TOLERANCE_M, STOP_ZONE_M
from .scenarios import (Scenario, entity, has_perception, monitor_scenario, monitors_of, spawn_facts, status_facts,
                        vehicle_action, vehicle_id, vehicle_scenario)
from .sensors import DEFAULT, POSITION_TOLERANCE_M, SPEED_TOLERANCE_MPS, Sensor, stated
from .signals import WORDS, Light, shown
from .state_samples import StateSamples

__all__ = [
    "ANTICIPATION_S", "AtChange", "Braking", "DEFAULT", "FOLLOW_M", "FOLLOW_S", "Junction", "LINE_EPS_M", "Light",
    "MAX_DECEL_MPS2", "MIN_DECEL_SPAN_S", "MOVING_MPS", "MPH_PER_MPS", "Map", "Other", "PAST_TOLERANCE_M",
    "POSITION_TOLERANCE_M", "Passage", "ROLE", "RunContext", "SPEED_TOLERANCE_MPS", "STOPPED_MPS", "STOP_ZONE_M",
    "Sample", "Scenario", "Sensor", "Standstill", "StateSamples", "UNIT", "VEHICLE_WIDTH_M", "WORDS", "between",
    "braking_into", "control_at", "entity", "from_events", "has_perception", "liability_facts", "monitor_scenario",
    "monitors_of", "mph", "own_cause", "passage", "passage_at", "passages", "paths_within", "peak_deceleration",
    "position_at", "project", "read_map", "role", "run_context", "sample_of", "samples", "sector", "shown", "since",
    "spawn_facts", "speed_at", "stated", "status_facts", "through", "user_id", "vehicle_action", "vehicle_id",
    "vehicle_scenario", "vehicle_src", "xy",
]
