"""bench/sim.py's reference drives the simulation's own traffic (issue 40: a fair reference).

The ratio issue 40 sets (the simulation, publishing, at half SUMO alone's speed or more) means
something only if SUMO alone steps the same traffic: here every vehicle the simulation puts on the
network is put there by the reference too, at the same step, with the same id, type and route,
read from what each handed to World.add_vehicle.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from sim_replay.maps import map_files
from sim_replay.simulation import Simulation
from sim_replay.sumo_world import World
from tests.helpers.script_module import load_script

BENCH_SIM = Path(__file__).resolve().parents[2] / "bench" / "sim.py"


def _added_by_the_simulation(config) -> list[tuple[int, str, str, tuple[str, ...]]]:
    """(step, id, type, route) of each vehicle the simulation put on the network."""
    added: list[tuple[int, str, str, tuple[str, ...]]] = []
    real = World.add_vehicle

    def logged(self, ident, kind, route, **kwargs):
        real(self, ident, kind, route, **kwargs)
        added.append((self._step, ident, kind, tuple(route)))

    World.add_vehicle = logged
    try:
        for _ in Simulation(config).batches(written=False):
            pass
    finally:
        World.add_vehicle = real
    return added


def test_the_reference_puts_the_simulations_vehicles_on_the_network_at_its_steps_on_its_routes():
    bench = load_script(BENCH_SIM, "bench_sim_reference")
    files = map_files("paper")
    args = argparse.Namespace(seed=3, vehicles=24, warmup=8.0, seconds=4.0, depart_within=0.6)
    config = bench.sim_config(files.net, files.monitors, args)
    simulated = _added_by_the_simulation(config)
    logged: list = []
    got = bench.sumo_same(files.net, files.monitors, args, log=logged)
    assert len(simulated) == 24 and got["added"] == 24
    assert logged == simulated
    assert got["vehicles_mean"] > 0 and got["steps_per_thread_cpu_s"] > 0
