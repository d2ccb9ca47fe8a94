"""kill -9 of a `gaps serve` child mid-stream, then a restart while the producer goes on: the store
verifies, and every event sent is stored (much of it recovered from the producer's caches) or listed
as a gap; none is lost silently. Two trials of bench/kill9.py's own trial (the bench runs 20)."""
from __future__ import annotations

import random
from pathlib import Path

import pytest

from tests.helpers.script_module import load_script

BENCH = Path(__file__).parents[2] / "bench" / "kill9.py"


@pytest.fixture(scope="module")
def kill9():
    return load_script(BENCH, "bench_kill9")


@pytest.mark.parametrize("seed", [3, 4])
def test_a_serve_killed_mid_stream_and_restarted_loses_nothing_silently(kill9, tmp_path: Path, seed: int) -> None:
    trial = kill9.trial(tmp_path, random.Random(seed), sources=5, rate=250, before_kill_s=(0.3, 0.8),
                        down_s=(0.0, 0.3), after_s=0.5)
    assert trial.verified
    assert trial.unaccounted == 0, trial
    assert trial.stored + trial.gap == trial.sent, trial
    assert trial.before_kill > 0 and trial.recovered > 0, trial     # it was killed mid-stream, and caches helped
