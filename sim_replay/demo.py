"""The run `gaps demo` simulates: the paper's map on SUMO, with a seeded mix of road users.

The paper (section 7.2) shows two cases at one signal junction: a car that enters on red
(punishable) and an ambulance on an emergency call that does (mitigated). The demo shows them
as the simulation makes them happen, beside two the rest of the system exists for: an automated
car whose camera misreads the light (a perception fault: the authorised self-driving entity is
liable) and a car rolling over a Stop line. Rates are raised well above real traffic so that a
three-minute run holds all four; the seed is one whose run does (tests/e2e/test_demo_sumo.py
checks it still does whenever the simulation or the rulebooks change).
"""
from __future__ import annotations

from .sim_config import Behaviour, FaultRates, SimConfig

DEMO_RUN = "demo-sumo"
DEMO = SimConfig(
    run=DEMO_RUN, seed=1, map="paper", vehicles=40, duration_s=180.0, av_share=0.4,
    emergency_share=0.2, on_call_share=0.8,
    behaviour=Behaviour(red_runner=0.3, stop_roller=0.4, amber_runner=0.1),
    faults=FaultRates(misperceived_light=0.5),
)
