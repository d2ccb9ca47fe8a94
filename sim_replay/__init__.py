"""Producers of recorded runs: the paper's scenarios, the multi-agent simulation and the SUMO world
it runs on, and publishing them on Zenoh.

These stand where vehicles, monitors and signals stand in DESIGN: they write events, and nothing in
the other rooms imports them: only `gaps demo`, the benchmarks and the tests do. The SUMO world
(`sumo_world`, `world_state`, `sumo_net`, `net_map`, `monitors`, `road_users`, `maps/`) is physics
and plumbing only: docs/simulation.md."""
