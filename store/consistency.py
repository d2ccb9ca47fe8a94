"""RFC 6962 consistency proofs between two sizes of a run's Merkle tree (store/merkle.py).

A signed tree head published outside the store says "run r had m events, with root R_m". Later
the store holds n >= m events with root R_n. A consistency proof is about log2(n) subtree roots
that let anyone holding only (m, R_m) and (n, R_n) check that the first m leaves of the larger
tree are exactly the leaves the smaller one was made of: the run was extended, never rewritten
or cut. (RFC 6962 section 2.1.2 makes the proof; RFC 9162 section 2.1.4.2 checks it.)

Every node of a proof is the root of a contiguous range of leaves, and the ranges of one proof
never overlap, so `proof_ranges` tells a caller which ranges to hash and `RangeRoots` computes
them in one pass over a run's events, without holding the run in memory.
"""

from __future__ import annotations

import hashlib
from typing import Sequence

from . import merkle

Range = tuple[int, int]  # [start, end) of leaves


def proof_ranges(m: int, n: int) -> list[Range]:
    """The leaf ranges whose roots make the consistency proof from size m to size n, in proof order."""
    if not 0 < m <= n:
        raise ValueError(f"a consistency proof needs 0 < m <= n, got m={m}, n={n}")
    return _subproof(m, 0, n, True)


def _subproof(m: int, lo: int, hi: int, complete: bool) -> list[Range]:
    """RFC 6962's SUBPROOF(m, D[lo:hi], b), as ranges."""
    size = hi - lo
    if m == size:
        return [] if complete else [(lo, hi)]
    k = _split(size)
    if m <= k:
        return [*_subproof(m, lo, lo + k, complete), (lo + k, hi)]
    return [*_subproof(m - k, lo + k, hi, False), (lo, lo + k)]


def _split(n: int) -> int:
    """The largest power of two smaller than n (n >= 2)."""
    return 1 << ((n - 1).bit_length() - 1)


def consistency_proof(leaves: Sequence[bytes], m: int) -> list[bytes]:
    """The proof that the first m leaves are a prefix of all of them (the reference: a caller
    with the leaves at hand; the store computes the same roots in one pass, RangeRoots)."""
    return [merkle.merkle_root(leaves[a:b]) for a, b in proof_ranges(m, len(leaves))]


def verify_consistency(m: int, n: int, root_m: bytes, root_n: bytes, proof: Sequence[bytes]) -> bool:
    """Does `proof` show that the tree of size m with root root_m is a prefix of the tree of size
    n with root root_n? (RFC 9162 2.1.4.2.)"""
    if not 0 < m <= n:
        return False
    if m == n:
        return not proof and root_m == root_n
    path = list(proof)
    if m & (m - 1) == 0:  # m a power of two: the old root is itself a node of the new tree
        path.insert(0, root_m)
    if not path:
        return False
    fn, sn = m - 1, n - 1
    while fn & 1:
        fn, sn = fn >> 1, sn >> 1
    fr = sr = path[0]
    for c in path[1:]:
        if sn == 0:
            return False
        if fn & 1 or fn == sn:
            fr, sr = _node(c, fr), _node(c, sr)
            while not fn & 1 and fn != 0:
                fn, sn = fn >> 1, sn >> 1
        else:
            sr = _node(sr, c)
        fn, sn = fn >> 1, sn >> 1
    return sn == 0 and fr == root_m and sr == root_n


def _node(left: bytes, right: bytes) -> bytes:
    return hashlib.sha256(merkle.NODE + left + right).digest()


class RangeRoots:
    """The roots of some disjoint leaf ranges, computed as the leaves stream past in order."""

    def __init__(self, ranges: Sequence[Range]) -> None:
        self._pending = sorted(ranges)
        self.roots: dict[Range, bytes] = {}
        self._frontier: list[bytes] = []
        self._i = 0  # index into _pending of the range being built

    def feed(self, position: int, leaf: bytes) -> None:
        """The leaf at this position (positions fed in order, from 0)."""
        while self._i < len(self._pending) and position >= self._pending[self._i][1]:
            self._i += 1
        if self._i == len(self._pending):
            return
        start, end = self._pending[self._i]
        if position < start:
            return
        merkle.push(self._frontier, position - start, leaf)
        if position == end - 1:
            self.roots[(start, end)] = merkle.root_of_frontier(self._frontier)
            self._frontier = []

    def proof(self, ranges: Sequence[Range]) -> list[bytes] | None:
        """The roots in proof order; None if the leaves stopped before a range was complete."""
        try:
            return [self.roots[r] for r in ranges]
        except KeyError:
            return None
