"""Merkle roots over a run's event hashes, recorded with every checkpoint.

The chain head proves a whole prefix of the run; a Merkle root proves the same prefix but also
lets one event be shown to belong to it with about log2(n) hashes (an inclusion proof), without
handing over the rest of the run.

The rule is RFC 6962's Merkle Tree Hash (Certificate Transparency), with the events' chain
hashes as the leaves taken as they are (they are already sha256 digests):

    root([h]) = h
    root(h[0:n]) = sha256(0x01 || root(h[0:k]) || root(h[k:n])),  k the largest power of 2 < n

No leaf is ever duplicated, so [a, b, c] and [a, b, c, c] have different roots. The root of
no events is sha256 of nothing; no checkpoint records it.

The store keeps a run's tree as its frontier: the roots of the perfect subtrees that the
binary digits of the event count split the leaves into, largest first. Adding a leaf merges
as many subtrees as the count has trailing one bits (one hash per leaf on average).
"""

from __future__ import annotations

import hashlib
from typing import Iterable, Sequence

NODE = b"\x01"  # prefix of an interior node, as in RFC 6962
EMPTY_ROOT = hashlib.sha256(b"").digest()
DIGEST_SIZE = 32


def push(frontier: list[bytes], count: int, leaf: bytes) -> None:
    """Add the leaf at position `count` (the number of leaves before it) to the frontier."""
    sha256 = hashlib.sha256
    node = leaf
    while count & 1:
        node = sha256(NODE + frontier.pop() + node).digest()
        count >>= 1
    frontier.append(node)


def root_of_frontier(frontier: Sequence[bytes]) -> bytes:
    """The Merkle root of the leaves a frontier stands for."""
    if not frontier:
        return EMPTY_ROOT
    node = frontier[-1]
    for left in reversed(frontier[:-1]):
        node = hashlib.sha256(NODE + left + node).digest()
    return node


def frontier_of(leaves: Iterable[bytes]) -> list[bytes]:
    """The frontier of a sequence of leaves, built one by one."""
    frontier: list[bytes] = []
    for count, leaf in enumerate(leaves):
        push(frontier, count, leaf)
    return frontier


def pack(frontier: Sequence[bytes]) -> str:
    """The frontier as a checkpoint stores it: its digests in hex, one after another."""
    return b"".join(frontier).hex()


def unpack(text: object, count: int) -> list[bytes] | None:
    """A stored frontier, or None if it cannot be the frontier of `count` leaves."""
    if not isinstance(text, str) or len(text) != 2 * DIGEST_SIZE * count.bit_count():
        return None
    try:
        blob = bytes.fromhex(text)
    except ValueError:
        return None
    if len(blob) != DIGEST_SIZE * count.bit_count():
        return None
    return [blob[i : i + DIGEST_SIZE] for i in range(0, len(blob), DIGEST_SIZE)]


def merkle_root(leaves: Sequence[bytes]) -> bytes:
    """RFC 6962's recursive definition, written out: the reference the frontier is tested against."""
    n = len(leaves)
    if n == 0:
        return EMPTY_ROOT
    if n == 1:
        return leaves[0]
    k = 1 << ((n - 1).bit_length() - 1)
    return hashlib.sha256(NODE + merkle_root(leaves[:k]) + merkle_root(leaves[k:])).digest()
