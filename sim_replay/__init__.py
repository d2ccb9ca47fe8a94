"""Producers of recorded runs: the paper's scenarios, a synthetic city run, and publishing them on Zenoh.

These stand where vehicles, monitors and signals stand in DESIGN: they write events, and nothing in
the other rooms imports them: only `gaps demo`, the benchmarks and the tests do."""
