"""An import pauses Python's cycle collector while the file streams through (store/transfer/feed.py):
it makes a few containers an event, all freed by reference counting, and the collector's passes
over them were 5% of an import's CPU. The collector must be back as it was afterwards, also when
the import fails half-way, and an import must leave it off if it was off."""

from __future__ import annotations

import gc

import pytest

from store import Store
from store.transfer import export_run, import_file
from tests.helpers.store_testkit import event


@pytest.fixture
def exported(tmp_path):
    with Store(tmp_path / "source.db") as store:
        store.append([event(seq, run="r", src="vehicle/1", t=1_000 + seq, kind="entity.state",
                            body={"x": 0.0, "y": 0.0, "heading_deg": 0.0, "speed_mps": 1.0}) for seq in range(30)])
        export_run(store, "r", tmp_path / "r.mcap")
    return tmp_path / "r.mcap"


def _collector_states_while_appending(store: Store, monkeypatch) -> list[bool]:
    seen: list[bool] = []
    append = store.append_candidates

    def watched(candidates):
        seen.append(gc.isenabled())
        return append(candidates)

    monkeypatch.setattr(store, "append_candidates", watched)
    return seen


def test_the_collector_is_paused_during_an_import_and_back_after(tmp_path, exported, monkeypatch):
    assert gc.isenabled()
    with Store(tmp_path / "into.db", durable=False) as store:
        seen = _collector_states_while_appending(store, monkeypatch)
        report = import_file(store, exported)
    assert report.stored == 30 and seen == [False]
    assert gc.isenabled()


def test_the_collector_comes_back_when_an_import_fails(tmp_path, exported, monkeypatch):
    with Store(tmp_path / "into.db", durable=False) as store:
        def failing(candidates):
            assert not gc.isenabled()
            raise RuntimeError("disk on fire")

        monkeypatch.setattr(store, "append_candidates", failing)
        with pytest.raises(RuntimeError, match="disk on fire"):
            import_file(store, exported)
    assert gc.isenabled()


def test_an_import_leaves_a_paused_collector_paused(tmp_path, exported):
    gc.disable()
    try:
        with Store(tmp_path / "into.db", durable=False) as store:
            assert import_file(store, exported).stored == 30
        assert not gc.isenabled()
    finally:
        gc.enable()
