"""RFC 6962 consistency proofs (store/consistency.py): made for any two sizes, they verify; any
other pair of roots, sizes or a changed proof node does not."""
from __future__ import annotations

import hashlib

from hypothesis import given, settings, strategies as st

from store import merkle
from store.consistency import RangeRoots, consistency_proof, proof_ranges, verify_consistency


def leaves(n: int, salt: bytes = b"") -> list[bytes]:
    return [hashlib.sha256(salt + i.to_bytes(4, "big")).digest() for i in range(n)]


def sizes(largest: int):
    """(m, n) with 1 <= m <= n <= largest: an older tree size and a newer one."""
    return st.integers(1, largest).flatmap(lambda n: st.tuples(st.integers(1, n), st.just(n)))


@settings(max_examples=300, deadline=None)
@given(sizes(300))
def test_a_proof_between_any_two_sizes_verifies(sizes):
    m, n = sizes
    all_leaves = leaves(n)
    proof = consistency_proof(all_leaves, m)
    assert verify_consistency(m, n, merkle.merkle_root(all_leaves[:m]), merkle.merkle_root(all_leaves), proof)
    assert len(proof) <= 2 * n.bit_length()


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 200).flatmap(lambda n: st.tuples(st.integers(1, n), st.just(n), st.integers(0, n - 1))))
def test_a_rewritten_prefix_or_altered_proof_fails(case):
    m, n, changed = case
    honest = leaves(n)
    root_m, root_n = merkle.merkle_root(honest[:m]), merkle.merkle_root(honest)
    forged = list(honest)
    forged[changed] = hashlib.sha256(b"forged").digest()
    proof = consistency_proof(forged, m)
    if changed < m:  # the old head names leaves the new tree no longer holds
        assert not verify_consistency(m, n, root_m, merkle.merkle_root(forged), proof)
    for i in range(len(proof)):
        bad = list(consistency_proof(honest, m))
        bad[i] = bytes(32)
        assert not verify_consistency(m, n, root_m, root_n, bad)
    if m < n:
        assert not verify_consistency(m, n, root_n, root_m, consistency_proof(honest, m))


def test_equal_sizes_need_no_proof_and_equal_roots():
    r = merkle.merkle_root(leaves(5))
    assert verify_consistency(5, 5, r, r, [])
    assert not verify_consistency(5, 5, r, bytes(32), [])
    assert not verify_consistency(0, 5, r, r, [])


@settings(max_examples=100, deadline=None)
@given(sizes(150))
def test_range_roots_streamed_are_the_proof(sizes):
    m, n = sizes
    all_leaves = leaves(n)
    ranges = proof_ranges(m, n)
    streamed = RangeRoots(ranges)
    for i, leaf in enumerate(all_leaves):
        streamed.feed(i, leaf)
    assert streamed.proof(ranges) == consistency_proof(all_leaves, m)
