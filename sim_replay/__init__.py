"""Producers of recorded runs: the paper's scenarios, the multi-agent simulation and the SUMO world
it runs on, and publishing them on Zenoh.

These stand where vehicles, monitors and signals stand in DESIGN: they write events, and nothing in
the other rooms imports them: only `gaps demo`, `gaps sim`, `gaps replay` (through the names
below, this room's face), the benchmarks and the tests do. The SUMO world
(`sumo_world`, `world_state`, `sumo_net`, `net_map`, `monitors`, `road_users`, `maps/`) is physics
and plumbing only: docs/simulation.md."""
from .demo import DEMO
from .held_runs import refuse_if_held_otherwise
from .outlets import OutletSummary, Outlets
from .own_network import OwnFilesError
from .paper import paper_run
from .replay import NothingToReplay, chosen_runs, recording
from .replay import replay as replay_runs       # the module keeps the name `sim_replay.replay`
from .sim_checks import RunTaken, refuse_second_producer, with_files
from .sim_config import FaultRates, SimConfig
from .simulation import Simulation

__all__ = ["DEMO", "FaultRates", "NothingToReplay", "OutletSummary", "Outlets", "OwnFilesError", "RunTaken",
           "SimConfig", "Simulation", "chosen_runs", "paper_run", "recording", "refuse_if_held_otherwise",
           "refuse_second_producer", "replay_runs", "with_files"]
