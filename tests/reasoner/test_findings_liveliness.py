"""The missing-evidence finding tells a source that stopped publishing (its liveliness token
disappeared after its last event) from one that was there and said nothing."""
from __future__ import annotations

from pathlib import Path

from reasoner.findings import SECOND, Gaps, missing_evidence
from store import Store
from store.wire import LivelinessChange
from tests.helpers.store_testkit import T0, event

SRC = "vehicle/173"


def _store(tmp_path: Path, *changes: LivelinessChange) -> Store:
    store = Store(tmp_path / "g.db")
    store.append([event(seq, src=SRC, kind="entity.state", t=T0 + seq * SECOND) for seq in range(5)])
    store.record_wire(changes)
    return store


def _details(store: Store, t: int) -> list[str]:
    return [f.detail for f in missing_evidence(Gaps(store, "r1"), [SRC], t, {SRC: T0 + 4 * SECOND})]


def test_a_source_whose_token_went_after_its_last_event_stopped_publishing(tmp_path: Path) -> None:
    with _store(tmp_path, LivelinessChange("r1", SRC, True, T0, None),
                LivelinessChange("r1", SRC, False, T0 + 5 * SECOND, 4)) as store:
        [detail] = _details(store, T0 + 6 * SECOND)        # only 2 s after its last event: not yet "silent"
    assert detail.startswith(f"{SRC} stopped publishing at 2024-11-21T10:15:04.000Z, 2.0 s before the incident")
    assert "liveliness token disappeared after its event 4" in detail


def test_a_source_still_connected_went_silent_and_it_is_said(tmp_path: Path) -> None:
    with _store(tmp_path, LivelinessChange("r1", SRC, True, T0, None)) as store:
        assert _details(store, T0 + 6 * SECOND) == []
        [detail] = _details(store, T0 + 20 * SECOND)
    assert detail.startswith(f"{SRC} went silent though it was connected: its liveliness token was held")


def test_without_liveliness_records_the_finding_is_as_before(tmp_path: Path) -> None:
    with _store(tmp_path) as store:
        [detail] = _details(store, T0 + 20 * SECOND)
    assert detail.startswith(f"{SRC} went silent: its last report before the incident was 16.0 s earlier")


def test_a_source_that_reported_at_the_incident_then_closed_took_nothing_from_it(tmp_path: Path) -> None:
    """The demo's publisher closes when its scenario is over: the vehicle's last event is the one
    at the incident's moment, so nothing before or at the incident is missing (issue 39)."""
    with _store(tmp_path, LivelinessChange("r1", SRC, True, T0, None),
                LivelinessChange("r1", SRC, False, T0 + 60 * SECOND, 4)) as store:
        assert _details(store, T0 + 4 * SECOND) == []


def test_the_ingests_wall_clock_is_not_mixed_into_the_runs_time(tmp_path: Path) -> None:
    with _store(tmp_path, LivelinessChange("r1", SRC, True, T0, None),
                LivelinessChange("r1", SRC, False, 1_796_000_000 * SECOND, 4)) as store:
        [detail] = _details(store, T0 + 6 * SECOND)
    assert "2026-" not in detail and "noticed" not in detail
