"""What `gaps verify` says of the cache file: which entries do not carry their seals.

Such entries are never used by a read (store/cache_seal.py): they are dropped and rebuilt from
the events. They change no verdict, so the store still verifies; but nothing this code runs
writes them, so someone who holds the folder did, and verify says so, as a warning.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from . import verified as verify_cache
from .derived import tampered_derived
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store
from .presence import tampered_presence
from .snapshots import tampered_snapshots


@dataclass(frozen=True)
class CacheTampering:
    """Per table, what of the cache does not carry its seal; and what reads dropped so far."""

    snapshots: dict[str, list[list]] = field(default_factory=dict)
    presence: dict[str, list[str]] = field(default_factory=dict)
    verifications: list[list] = field(default_factory=list)
    derived: dict[str, list[str]] = field(default_factory=dict)
    dropped_by_reads: dict[str, int] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not (self.snapshots or self.presence or self.verifications or self.derived or self.dropped_by_reads)

    def count(self) -> int:
        return sum(map(len, self.snapshots.values())) + sum(map(len, self.presence.values())) + len(self.verifications) \
            + sum(map(len, self.derived.values()))

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "snapshots": self.snapshots, "presence": self.presence,
                "verifications": self.verifications, "derived": self.derived, "dropped_by_reads": self.dropped_by_reads}


def cache_tampering(store: Store, runs: list[str]) -> CacheTampering:
    """The cache's entries of these runs (and every recorded verification) whose seals do not
    open; a store without a cache file is left without one."""
    if not store.cache.exists():
        return CacheTampering()
    snaps = {run: [list(p) for p in found] for run in runs if (found := tampered_snapshots(store, run))}
    boxes = {run: bad for run in runs if (bad := tampered_presence(store, run))}
    verifications = [list(key) for key in verify_cache.unsealed(store.cache)]
    derived = {run: unsealed for run in runs if (unsealed := tampered_derived(store, run))}
    return CacheTampering(snaps, boxes, verifications, derived, store.cache.sealer.tampered())
