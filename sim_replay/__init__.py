"""Producers of recorded runs: the paper's scenarios, the multi-agent simulation and the SUMO world
it runs on, and publishing them on Zenoh.

These stand where vehicles, monitors and signals stand in DESIGN: they write events, and nothing in
the other rooms imports them: only `gaps demo`, `gaps sim`, `gaps replay` (through the names
below, this room's face), the benchmarks and the tests do. The SUMO world
(`sumo_world`, `world_state`, `sumo_net`, `net_map`, `monitors`, `road_users`, `maps/`) is physics
and plumbing only: docs/simulation.md."""
from .demo import DEMO
from .held_runs import refuse_if_held_otherwise
from .maps import map_files
from .outlets import OutletSummary, Outlets
from .own_network import OwnFilesError, own_files
from .own_network import check as check_own_network
from .paper import paper_run
from .replay import NothingToReplay, chosen_runs, recording
from .replay import replay as replay_runs       # the module keeps the name `sim_replay.replay`
from .sim_config import FaultRates, SimConfig
from .simulation import Simulation

__all__ = ["DEMO", "FaultRates", "NothingToReplay", "OutletSummary", "Outlets", "OwnFilesError", "SimConfig",
           "Simulation", "check_own_network", "chosen_runs", "map_files", "own_files", "paper_run", "recording",
           "refuse_if_held_otherwise", "replay_runs"]
