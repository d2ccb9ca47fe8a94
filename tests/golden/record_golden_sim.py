"""Record the golden run `golden-sim` again (tests/golden/golden-sim.mcap): 60 road users on the
paper's map for 90 s at 5 Hz, seed 5, habits and the misread-light fault raised so that red,
amber, Stop, Give Way, speeding and emergency acts happen. The same config gives the same events
(sim_replay/sim_config.py); a new SUMO or simulation may not, which is why the recording, not this
script, is the golden run. After re-recording, approve its verdicts:

    python tests/golden/record_golden_sim.py
    gaps regress --golden tests/golden/golden-sim.json --update-golden
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from sim_replay.sim_config import Behaviour, FaultRates, SimConfig
from sim_replay.simulation import Simulation
from store import Store
from store.transfer import export_run

HERE = Path(__file__).parent
CONFIG = SimConfig(run="golden-sim", vehicles=60, duration_s=90.0, seed=5, rate_hz=5.0, emergency_share=0.15,
                   pedestrians=8, av_share=0.4,
                   behaviour=Behaviour(red_runner=0.3, amber_runner=0.4, stop_roller=0.4, no_give_way=0.4,
                                       speeder=0.2),
                   faults=FaultRates(misperceived_light=0.5))


def main(out: Path = HERE / "golden-sim.mcap") -> None:
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "gaps.db") as store:
        store.append(list(Simulation(CONFIG).events()))
        report = export_run(store, CONFIG.run, out, scene=False)
    print(f"{out}: {report.events} events, {out.stat().st_size} bytes", file=sys.stderr)


if __name__ == "__main__":
    main()
