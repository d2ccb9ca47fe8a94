"""The collector around a judgement: paused while judging, what is left frozen at the end, and
cycles made between two judgements reclaimed when the next one starts (memory stays bounded)."""
from __future__ import annotations

import gc
import weakref

import pytest

from reasoner.collector import JudgementCollector


class _Node:
    def __init__(self) -> None:
        self.me = self          # a cycle: only the collector frees it


@pytest.fixture(autouse=True)
def _restore_collector():
    was = gc.isenabled()
    yield
    gc.unfreeze()
    (gc.enable if was else gc.disable)()


def test_the_collector_is_paused_while_judging_and_on_again_after() -> None:
    gc.enable()
    with JudgementCollector():
        assert not gc.isenabled()
    assert gc.isenabled()


def test_what_a_judgement_leaves_is_frozen_out_of_full_passes() -> None:
    gc.enable()
    gc.unfreeze()
    with JudgementCollector():
        kept = [[i] for i in range(1000)]
    assert gc.get_freeze_count() >= 1000
    old = {id(o) for o in gc.get_objects(generation=2)}
    assert not any(id(k) in old for k in kept)


def test_a_cycle_left_between_judgements_is_reclaimed_when_the_next_starts() -> None:
    gc.enable()
    with JudgementCollector():
        node = _Node()
    alive = weakref.ref(node)
    del node
    gc.collect()                        # frozen: a full pass does not reach it
    assert alive() is not None
    with JudgementCollector():
        assert alive() is None          # unfrozen and collected before judging


def test_a_caller_that_switched_the_collector_off_is_left_alone() -> None:
    gc.unfreeze()
    gc.disable()
    with JudgementCollector():
        kept = [[1], [2]]
    assert not gc.isenabled()
    assert gc.get_freeze_count() == 0
    assert kept
