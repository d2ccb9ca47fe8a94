"""Fixtures for the ingest tests (helpers live in ingest_testkit, a name no other test folder uses)."""
from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from ingest import IngestService
from tests.helpers.ingest_testkit import linked
from sim_replay.publisher import EventPublisher


@pytest.fixture
def db_path(tmp_path: Path) -> Path:
    return tmp_path / "gaps.db"


@pytest.fixture
def link(db_path: Path) -> Iterator[tuple[EventPublisher, IngestService]]:
    """The default pairing: the publisher listens, the ingest connects as a peer."""
    with linked(db_path, "pub-listens") as pair:
        yield pair
