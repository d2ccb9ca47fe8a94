"""The collector's thresholds are raised while a writer runs and put back when the last one stops."""
from __future__ import annotations

import gc
from collections.abc import Iterator

import pytest

from ingest.gc_pacing import WRITER_THRESHOLDS, batch_sized_collections


@pytest.fixture
def default_thresholds() -> Iterator[None]:
    saved = gc.get_threshold()
    gc.set_threshold(700, 10, 10)
    yield
    gc.set_threshold(*saved)


def test_raised_while_writers_run_and_restored_after_the_last(default_thresholds: None) -> None:
    with batch_sized_collections():
        assert gc.get_threshold() == WRITER_THRESHOLDS
        with batch_sized_collections():             # a second writer in the same process
            assert gc.get_threshold() == WRITER_THRESHOLDS
        assert gc.get_threshold() == WRITER_THRESHOLDS   # the first still runs
    assert gc.get_threshold() == (700, 10, 10)


def test_never_lowers_what_the_process_set_and_restores_after_an_error(default_thresholds: None) -> None:
    gc.set_threshold(100_000, 5, 20)
    with pytest.raises(RuntimeError), batch_sized_collections():
        assert gc.get_threshold() == (100_000, 10, 20)
        raise RuntimeError("the writer failed")
    assert gc.get_threshold() == (100_000, 5, 20)
