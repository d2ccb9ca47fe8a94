"""kill -9 of a `gaps serve` child mid-stream, then a restart while the producer goes on: the store
verifies, and every event sent is stored (much of it recovered from the producer's caches) or listed
as a gap; none is lost silently. Trials of bench/kill9.py's own trial, in every documented topology:
the serve connecting to a listening producer, the serve listening with the producer connecting to
it (docs/serve.md), where the producer must find the restarted serve again by itself, and both
clients of a Zenoh router."""
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


@pytest.mark.parametrize("topology", ["serve-connects", "serve-listens", "via-router"])
def test_a_serve_down_for_seconds_recovers_everything_in_every_topology(kill9, tmp_path: Path,
                                                                         topology: str) -> None:
    """Down 2.5-3.5 s, then half a second of publishing before the producer closes: a serve that
    listens is found again only when the producer's session tries its endpoint again, which with
    Zenoh's own schedule (1, 2, 4, 4 s apart) came after the producer had closed, and everything
    after the kill was lost silently; the serve that connects dials at once."""
    trial = kill9.trial(tmp_path, random.Random(5), sources=5, rate=250, before_kill_s=(0.3, 0.8),
                        down_s=(2.5, 3.5), after_s=0.5, topology=topology)
    assert trial.verified
    assert trial.unaccounted == 0 and trial.gap == 0, trial
    assert trial.stored == trial.sent, trial
    assert trial.recovered > 0, trial
