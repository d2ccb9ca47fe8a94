"""The simulation holds the garbage collector back while it ticks, and gives the thresholds back after."""
from __future__ import annotations

import gc

import pytest

from sim_replay.collector import THRESHOLD, fewer_collections
from sim_replay.sim_config import SimConfig
from sim_replay.simulation import Simulation


@pytest.fixture
def thresholds():
    before = gc.get_threshold()
    yield
    gc.set_threshold(*before)


def test_the_first_threshold_is_raised_inside_and_put_back_after(thresholds):
    gc.set_threshold(700, 11, 12)
    with fewer_collections():
        assert gc.get_threshold() == (THRESHOLD, 11, 12)
    assert gc.get_threshold() == (700, 11, 12)


def test_put_back_after_an_error_too(thresholds):
    gc.set_threshold(700, 10, 10)
    with pytest.raises(RuntimeError), fewer_collections():
        raise RuntimeError("a tick failed")
    assert gc.get_threshold() == (700, 10, 10)


@pytest.mark.parametrize("already", [0, 3 * THRESHOLD])
def test_a_higher_threshold_or_automatic_collection_off_is_left_alone(thresholds, already):
    gc.set_threshold(already, 10, 10)
    with fewer_collections():
        assert gc.get_threshold() == (already, 10, 10)


def test_a_run_ticks_with_the_higher_threshold_and_ends_with_the_old_one(thresholds):
    gc.set_threshold(700, 10, 10)
    seen = []
    for _ in Simulation(SimConfig(vehicles=2, duration_s=2.0, pedestrians=0)).events():
        seen.append(gc.get_threshold()[0])
    assert seen and set(seen) == {THRESHOLD}
    assert gc.get_threshold() == (700, 10, 10)
