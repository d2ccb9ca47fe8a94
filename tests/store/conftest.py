"""Fixtures shared by the store tests."""

from __future__ import annotations

from pathlib import Path
from typing import Iterator

import pytest

from store import Store


@pytest.fixture
def db_path(tmp_path: Path) -> Path:
    return tmp_path / "gaps.db"


@pytest.fixture
def store(db_path: Path) -> Iterator[Store]:
    with Store(db_path) as opened:
        yield opened
