"""The per-run hash chain that makes the log tamper-evident.

Each event's hash covers the previous hash, so changing, removing or reordering any stored
event changes every hash after it; checkpoints recorded elsewhere then expose the rewrite.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

from . import merkle

GENESIS = bytes(32)  # the "previous hash" of a run's first event


def is_digest_hex(value: object) -> bool:
    """Whether a stored or received value is a sha256 digest as hex (64 hex digits)."""
    if not isinstance(value, str) or len(value) != 64:
        return False
    try:
        bytes.fromhex(value)
    except ValueError:
        return False
    return True


def link(prev: bytes, canonical: bytes) -> bytes:
    """sha256(prev || canonical): the hash of an event given the hash before it."""
    return hashlib.sha256(prev + canonical).digest()


@dataclass(slots=True)
class RunChain:
    """Where a run's chain stands: events in it, head hash, Merkle frontier, and the event
    count at its latest checkpoint."""

    count: int = 0
    head: bytes = GENESIS
    frontier: list[bytes] = field(default_factory=list)
    checkpointed: int = 0

    def extend(self, canonical: bytes) -> bytes:
        """Chain one more event; return its hash."""
        digest = hashlib.sha256(self.head + canonical).digest()
        merkle.push(self.frontier, self.count, digest)
        self.count += 1
        self.head = digest
        return digest

    def root(self) -> bytes:
        return merkle.root_of_frontier(self.frontier)
