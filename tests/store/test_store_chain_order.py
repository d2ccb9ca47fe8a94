"""The chain order that travels beside a time-ordered MCAP file: written compactly, read back
exactly, and followed on import without holding more than a bounded number of events back."""

from __future__ import annotations

import zlib

import pytest

from store import Candidate
from store.transfer import chain_order
from store.transfer.chain_order import Reorder, decode, encode


def test_keys_come_back_exactly_including_gaps_and_seqs_out_of_order():
    keys = [("vehicle/1", 0), ("vehicle/2", 0), ("vehicle/1", 1), ("vehicle/1", 5), ("vehicle/2", 1),
            ("vehicle/1", 3), ("monitor/m", 2**40), ("vehicle/1", 6)]
    order = decode(encode("r", keys))
    assert (order.run, order.events, list(order.keys())) == ("r", len(keys), keys)


def test_a_long_regular_run_costs_little():
    keys = [(f"vehicle/{i % 200}", i // 200) for i in range(200_000)]
    data = encode("r", keys)
    assert len(data) < 20_000  # under a tenth of a byte an event once compressed
    assert list(decode(data).keys()) == keys


@pytest.mark.parametrize("damage", [b"not zlib", zlib.compress(b'{"format":"other"}\n'),
                                    encode("r", [("a", 0), ("a", 1)])[:-3],
                                    zlib.compress(b'{"format":"gaps.chain_order v1","run":"r","events":3,'
                                                  b'"sources":["a"]}\n\x00\x00')])
def test_a_damaged_chain_order_is_refused_whole(damage):
    with pytest.raises(ValueError, match="not a readable chain order"):
        decode(damage)


def candidate(src: str, seq: int, run: str = "r") -> Candidate:
    ev = {"v": 1, "run": run, "src": src, "seq": seq, "t": seq, "kind": "vehicle.perception", "body": {}}
    return Candidate(f"{src}#{seq}", b"", ev, b"")


def released(reorder: Reorder, arrivals: list[tuple[str, int]]) -> list[tuple[str, int]]:
    out = [c for key in arrivals for c in reorder.push(candidate(*key))] + reorder.finish()
    return [(c.event["src"], c.event["seq"]) for c in out]


def test_events_go_out_in_chain_order_as_soon_as_their_turn_comes():
    chain = [("b", 0), ("a", 0), ("a", 1), ("b", 1)]
    reorder = Reorder()
    reorder.expect(decode(encode("r", chain)))
    assert reorder.push(candidate("a", 0)) == []
    assert [c.event["seq"] for c in reorder.push(candidate("b", 0))] == [0, 0]
    assert released(reorder, [("b", 1), ("a", 1)]) == [("a", 1), ("b", 1)]
    assert reorder.abandoned == []


def test_a_missing_event_holds_back_no_more_than_the_bound():
    chain = [("a", i) for i in range(10)]
    reorder = Reorder(max_held=3)
    reorder.expect(decode(encode("r", chain)))
    arrivals = [("a", i) for i in range(1, 10)]  # a:0 never comes
    out = []
    for key in arrivals:
        out += reorder.push(candidate(*key))
        assert sum(len(state.held) for state in reorder._runs.values()) <= 3
    out += reorder.finish()
    assert [(c.event["src"], c.event["seq"]) for c in out] == arrivals and reorder.abandoned == ["r"]


def test_other_runs_and_unparsed_input_pass_straight_through():
    reorder = Reorder()
    reorder.expect(decode(encode("r", [("a", 1), ("a", 0)])))
    other = candidate("a", 0, run="other")
    refused = Candidate("line 3", b"{", reason="not JSON")
    assert reorder.push(other) == [other] and reorder.push(refused) == [refused]
    assert reorder.push(candidate("x", 0)) == []  # of run r, but not in its chain order: held to the end
    assert released(reorder, [("a", 0), ("a", 1)]) == [("a", 1), ("a", 0), ("x", 0)]


def test_the_attachment_is_named_for_what_it_holds():
    assert chain_order.ATTACHMENT == "gaps.chain_order" and chain_order.MEDIA_TYPE.endswith("+zlib")


def test_an_attachment_that_inflates_past_the_bound_is_refused(monkeypatch):
    monkeypatch.setattr(chain_order, "MAX_BYTES", 1000)
    with pytest.raises(ValueError, match="inflates to more than 1000 bytes"):
        decode(zlib.compress(b"\x00" * 5000))
