"""How long the fuzzers run: a few examples each in the ordinary test run (CI, `make test`: the
whole of tests/fuzz in about 20-30 s on a loaded machine), ten times as many under `make fuzz`
(GAPS_FUZZ=long), which the Makefile repeats with fresh seeds for ten minutes. A failing example Hypothesis finds is kept in
its database (.hypothesis/) and tried first next time."""
from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

LONG = os.environ.get("GAPS_FUZZ") == "long"


def fuzz(examples: int):
    """Settings for a fuzzer that runs `examples` examples in CI and ten times as many under make fuzz."""
    return settings(max_examples=examples * 10 if LONG else examples, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.function_scoped_fixture])
