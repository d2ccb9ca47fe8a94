"""The per-run hash chain that makes the log tamper-evident.

Each event's hash covers the previous hash, so changing, removing or reordering any stored
event changes every hash after it; checkpoints recorded elsewhere then expose the rewrite.
"""

from __future__ import annotations

import hashlib

GENESIS = bytes(32)  # the "previous hash" of a run's first event


def link(prev: bytes, canonical: bytes) -> bytes:
    """sha256(prev || canonical): the hash of an event given the hash before it."""
    digest = hashlib.sha256(prev)
    digest.update(canonical)
    return digest.digest()
