"""screen takes a fast lane for the common sample (a canonical event put on its own key as JSON);
every sample must end exactly where the general road ends: the same candidate (bytes kept, event,
canonical bytes the store hashes, reason for a refusal) and the same identity for gap tracking."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ingest.screen as screen_module
from ingest.screen import _general, screen, screen_all
from store import canonical_json, decode_event
from store.wire import key_for
from store.kinds import KINDS
from tests.helpers.store_testkit import BODIES, event

_numbers = st.floats() | st.integers(min_value=-(2 ** 64), max_value=2 ** 64) | st.sampled_from([1e-5, 1e16, 0.0, -0.0])
_twists = [
    lambda raw: raw,
    lambda raw: raw.replace(b',', b', ', 1),
    lambda raw: raw.replace(b'"v":1', b'"v":2', 1),
    lambda raw: raw.replace(b'"seq":', b'"seq":1,"seq":', 1),
    lambda raw: raw.replace(b'}', b',"sig":{}}', 1),
    lambda raw: raw[:-2],
    lambda raw: b"\xff" + raw,
]


@st.composite
def samples(draw):
    kind = draw(st.sampled_from(sorted(KINDS)))
    body = dict(BODIES[kind])
    for name in draw(st.lists(st.sampled_from([*body, "extra"]), max_size=2)):
        body[name] = draw(_numbers | st.text(max_size=3) | st.none())
    ev = event(draw(st.integers(0, 5)), kind=kind, body=body, src=draw(st.sampled_from([None, "vehicle/9", "sim/w"])))
    try:
        raw = draw(st.just(_twists[0]) | st.sampled_from(_twists))(canonical_json(ev))  # half as sent
    except (ValueError, TypeError):
        raw = repr(ev).encode()
    key = draw(st.sampled_from([key_for(ev), key_for({**ev, "src": "vehicle/other"}), "gaps/r1"]))
    encoding = draw(st.just("application/json") | st.sampled_from(["application/json;schema", "zenoh/bytes", "text/plain"]))
    return key, raw, draw(st.booleans()) or draw(st.booleans()), encoding


@pytest.fixture(autouse=True, scope="module")
def _meet_every_source() -> None:
    """Every (kind, src) the samples use met before, so that the fast lane is open to each."""
    for kind in KINDS:
        for src in (None, "vehicle/9", "sim/w"):
            try:
                decode_event(canonical_json(event(kind=kind, src=src)))
            except ValueError:
                pass


@settings(deadline=None, max_examples=250)
@given(samples())
def test_the_fast_lane_ends_where_the_general_road_ends(sample) -> None:
    key, raw, is_put, encoding = sample
    assert screen(key, raw, is_put=is_put, encoding=encoding) == _general(key, raw, is_put, encoding)


def test_the_common_sample_takes_the_fast_lane(monkeypatch) -> None:
    ev = event(kind="entity.state")
    raw = canonical_json(ev)
    screen(key_for(ev), raw)  # the source met
    monkeypatch.setattr(screen_module, "_general", lambda *a: (_ for _ in ()).throw(AssertionError("general road")))
    item = screen(key_for(ev), raw)
    assert item.identity == ("r1", ev["src"], 0)
    assert item.candidate.reason is None and item.candidate.canonical is raw and item.candidate.event == ev


@settings(deadline=None, max_examples=100)
@given(st.lists(samples(), max_size=8))
def test_a_batch_screened_in_one_loop_ends_where_each_sample_ends_on_the_general_road(batch) -> None:
    """The writer screens a whole take in one loop (screen_all): same verdicts, same order."""
    def failed(key: str, payload: bytes, exc: Exception) -> None:
        raise AssertionError(f"screening raised on {key}: {exc!r}")

    assert screen_all(batch, failed) == [_general(*sample) for sample in batch]


def test_a_sample_whose_screening_raises_gets_the_callers_verdict_and_costs_no_other(monkeypatch) -> None:
    good = [(key_for(ev), canonical_json(ev), True, "application/json") for ev in (event(0), event(1), event(2))]
    real = screen_module.plain_event

    def plain_event(raw: bytes):
        if raw == good[1][1]:
            raise RuntimeError("a bug")
        return real(raw)

    monkeypatch.setattr(screen_module, "plain_event", plain_event)
    verdicts = screen_all(good, lambda key, payload, exc: ("failed", key, payload, repr(exc)))
    assert verdicts[1] == ("failed", good[1][0], good[1][1], "RuntimeError('a bug')")
    assert [verdicts[0], verdicts[2]] == [_general(*good[0]), _general(*good[2])]
    with pytest.raises(RuntimeError, match="a bug"):   # screen alone leaves a failure to its caller
        screen(*good[1][:2])
