"""Automatic collection is off while a writer runs and put back as it was when the last one stops;
each writer collects between its batches, the young generation every time, older ones less often."""
from __future__ import annotations

import gc
from collections.abc import Iterator

import pytest

from ingest import gc_pacing
from ingest.gc_pacing import MIDDLE_EVERY, collections_between_batches


@pytest.fixture
def collector_on() -> Iterator[None]:
    was = gc.isenabled()
    gc.enable()
    yield
    gc.enable() if was else gc.disable()


def test_off_while_writers_run_and_back_after_the_last(collector_on: None) -> None:
    with collections_between_batches():
        assert not gc.isenabled()
        with collections_between_batches():             # a second writer in the same process
            assert not gc.isenabled()
        assert not gc.isenabled()                        # the first still runs
    assert gc.isenabled()


def test_left_off_if_the_process_had_it_off_and_back_after_an_error(collector_on: None) -> None:
    gc.disable()
    with collections_between_batches():
        pass
    assert not gc.isenabled()
    gc.enable()
    with pytest.raises(RuntimeError), collections_between_batches():
        raise RuntimeError("the writer failed")
    assert gc.isenabled()


def test_between_batches_collects_the_young_often_and_everything_by_the_clock(
        monkeypatch: pytest.MonkeyPatch) -> None:
    asked: list[int] = []
    monkeypatch.setattr(gc_pacing.gc, "collect", lambda generation=2: asked.append(generation) or 0)
    now = [100.0]
    collect = gc_pacing._between_batches(clock=lambda: now[0])
    for _ in range(2 * MIDDLE_EVERY):
        collect()
    assert asked == ([0] * (MIDDLE_EVERY - 1) + [1]) * 2
    now[0] += gc_pacing.FULL_EVERY_S
    collect()
    assert asked[-1] == 2


def test_a_cycle_made_while_a_writer_runs_is_collected_between_its_batches() -> None:
    class Node:
        pass

    with collections_between_batches() as between_batches:
        first, second = Node(), Node()
        first.other, second.other = second, first
        ident = id(first)
        del first, second
        assert any(id(o) == ident for o in gc.get_objects(generation=0))   # not collected by itself
        between_batches()
        assert not any(id(o) == ident for o in gc.get_objects())
