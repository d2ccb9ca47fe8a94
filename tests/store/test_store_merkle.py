"""Merkle roots: RFC 6962's tree hash over the event hashes, kept incrementally as a frontier."""

import hashlib

import pytest
from hypothesis import given, settings, strategies as st

from store import merkle


def leaf(i: int) -> bytes:
    return hashlib.sha256(str(i).encode()).digest()


def node(left: bytes, right: bytes) -> bytes:
    return hashlib.sha256(b"\x01" + left + right).digest()


def test_small_trees_written_out():
    a, b, c, d, e = (leaf(i) for i in range(5))
    assert merkle.merkle_root([a]) == a
    assert merkle.merkle_root([a, b]) == node(a, b)
    assert merkle.merkle_root([a, b, c]) == node(node(a, b), c)
    assert merkle.merkle_root([a, b, c, d]) == node(node(a, b), node(c, d))
    assert merkle.merkle_root([a, b, c, d, e]) == node(node(node(a, b), node(c, d)), e)


def test_no_leaf_is_duplicated():
    a, b, c = (leaf(i) for i in range(3))
    assert merkle.merkle_root([a, b, c]) != merkle.merkle_root([a, b, c, c])


def test_empty_tree():
    assert merkle.merkle_root([]) == merkle.root_of_frontier([]) == hashlib.sha256(b"").digest()


@settings(deadline=None, max_examples=60)
@given(st.integers(min_value=1, max_value=600))
def test_frontier_gives_the_reference_root_at_every_size(n):
    leaves = [leaf(i) for i in range(n)]
    frontier = merkle.frontier_of(leaves)
    assert len(frontier) == n.bit_count()
    assert merkle.root_of_frontier(frontier) == merkle.merkle_root(leaves)


def test_push_one_by_one_matches_every_prefix():
    leaves = [leaf(i) for i in range(70)]
    frontier: list[bytes] = []
    for count, value in enumerate(leaves):
        merkle.push(frontier, count, value)
        assert merkle.root_of_frontier(frontier) == merkle.merkle_root(leaves[: count + 1])


def test_pack_and_unpack():
    frontier = merkle.frontier_of(leaf(i) for i in range(11))
    text = merkle.pack(frontier)
    assert text == b"".join(frontier).hex()
    assert merkle.unpack(text, 11) == frontier


@pytest.mark.parametrize("text, count", [
    ("ab" * 32, 3),        # 3 leaves need two subtree roots
    ("zz" * 32, 1),        # not hex
    ("ab " * 32, 1),       # hex with spaces decodes shorter
    (None, 1),
    (b"\x00" * 32, 1),     # bytes, not text
])
def test_unpack_refuses_what_cannot_be_a_frontier(text, count):
    assert merkle.unpack(text, count) is None
