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


def reseal_snapshots(store: Store) -> None:
    """Seal every state snapshot again under the cache's key, as whoever holds that key could after
    altering one: what is left to catch it is `check_snapshots`' re-fold."""
    from store.cache import snapshots
    conn, sealer = store.cache.connection, store.cache.sealer
    for run, fold, t, seq, src, n, head, blob, epoch in conn.execute(
            "SELECT run, fold, t, seq, src, chain_len, head, state, epoch FROM state_snapshots").fetchall():
        mac = sealer.seal(snapshots.SNAPSHOTS, (run, fold, t, seq, src, n, head), (blob, epoch))
        conn.execute("UPDATE state_snapshots SET mac = ? WHERE run = ? AND fold = ? AND t = ? AND seq = ? AND src = ?",
                     (mac, run, fold, t, seq, src))
