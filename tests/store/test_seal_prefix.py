"""A run's kept entries of one kind share all of what names them but their key, so their seals
are checked after that part is framed once (Sealer.prefix, Sealer.opens_after): the very seal
`Sealer.seal` makes, and a wrong one still dropped and counted."""
from __future__ import annotations

import pytest

from store.cache.seal import Sealer

NAMES = ("run-1", "measurement", "v1", 12, "head")


@pytest.mark.parametrize("payload", ["", "x" * 5000, "é\ud800 text", b"raw", ("text", 3, 1.5, None, True)])
def test_a_seal_opens_after_its_names_framed_once(payload) -> None:
    sealer = Sealer(b"k" * 32)
    prefix = sealer.prefix("derived", NAMES)
    assert sealer.opens_after("derived", prefix, "key", payload, sealer.seal("derived", (*NAMES, "key"), payload))
    assert sealer.dropped == {}


def test_a_seal_of_another_key_or_payload_does_not_open_and_is_counted() -> None:
    sealer = Sealer(b"k" * 32)
    prefix = sealer.prefix("derived", NAMES)
    seal = sealer.seal("derived", (*NAMES, "key"), "payload")
    assert not sealer.opens_after("derived", prefix, "other key", "payload", seal)
    assert not sealer.opens_after("derived", prefix, "key", "payload!", seal)
    assert not sealer.opens_after("derived", sealer.prefix("derived", NAMES[:-1]), "key", "payload", seal)
    assert not sealer.opens_after("derived", prefix, "key", "payload", None)
    assert sealer.dropped == {"derived": 4}
