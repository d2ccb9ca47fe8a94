"""Decide, per received sample, what the store should do with it, and what it tells us about gaps.

Validity is the store's definition: its own parser runs here, once, and the result goes to
``Store.append_candidates`` so the store does not parse again. The ingest adds the one check only it
can make: does the Zenoh key agree with the event it carries? An event for vehicle/173 arriving on
vehicle/174's key is misrouted or forged; routing by key (slices of the key space per ingest, per-key
subscriptions downstream) would otherwise trust the wrong identity. A sample whose declared Zenoh encoding
says it is not JSON (CBOR, protobuf, an image) is refused for what it claims to be: DESIGN puts events on
the wire as ``application/json``; one that declares nothing carries Zenoh's default ``zenoh/bytes`` and is
judged by its content, as foreign producers often declare nothing. DELETE samples are refused too: the
log is append-only.
"""
from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from functools import partial
from typing import NamedTuple

from store import MAX_EVENT_BYTES, Candidate, EventError, decode_event, plain_event
from store.keys import TrustedKeys
from store.wire import key_for

from .inbox import Received

# An oversized event is refused by the store without being parsed, but it did arrive, so its seq should
# still count as seen. Beyond this size even reading the identity would stall the writer.
MAX_IDENTITY_BYTES = 8 * MAX_EVENT_BYTES

Identity = tuple[str, str, int]  # (run, src, seq)

JSON_ENCODINGS = frozenset({"application/json", "text/json", "zenoh/bytes", "zenoh/string"})
"""Declared encodings under which a payload may be an event: JSON itself, or none declared (Zenoh's
default, ``zenoh/bytes``, and its UTF-8 variant). A schema suffix (``;...``) is ignored."""


class Screened(NamedTuple):
    """A store candidate, and the (run, src, seq) it arrived as, if known, for gap tracking.

    An event that arrived counts as seen even if the store quarantines it: a gap means "never arrived",
    not "not stored". A misrouted event's identity is not trusted, so it has none.
    """

    candidate: Candidate
    identity: Identity | None


Failed = Callable[[str, bytes, Exception], Screened]  # the verdict on a sample whose screening raised


def screen(key: str, payload: bytes, *, is_put: bool = True, encoding: str = "application/json") -> Screened:
    """Parse once; refuse deletes, foreign encodings and key/body mismatches; let the store judge
    everything else. The common sample (a canonical event on its own key) takes one road through
    the store's plain_event; anything else the general one, which decides alike for it too."""
    return screen_all(((key, payload, is_put, encoding),), _raise)[0]


def screen_all(samples: Iterable[Received], failed: Failed) -> list[Screened]:
    """``screen`` of each (key, payload, is_put, encoding), in order, in one loop: the writer's
    hot path, where a call, keyword arguments and a dataclass per sample were a tenth of its
    Python time. A sample whose screening raises (a bug: screening refuses, it does not raise)
    gets ``failed(key, payload, exc)``'s verdict instead, and costs no other sample its own."""
    out: list[Screened] = []
    append = out.append
    for key, payload, is_put, encoding in samples:
        try:
            if is_put and encoding == "application/json":
                plain = plain_event(payload)
                if plain is not None:
                    ev, run, src, seq, kind = plain
                    if key == f"gaps/{run}/{src}/{kind}":  # key_for(ev), its parts already at hand
                        append(_screened((_candidate((key, payload, ev, payload, None)), (run, src, seq))))
                        continue
            append(_general(key, payload, is_put, encoding))
        except Exception as exc:
            append(failed(key, payload, exc))
    return out


# Screened and Candidate from their fields' tuple, in C: no Python __new__ or __init__ per sample
_screened = partial(tuple.__new__, Screened)
_candidate = partial(tuple.__new__, Candidate)


def _raise(key: str, payload: bytes, exc: Exception) -> Screened:
    """``screen``'s answer to a failure: the caller's to handle."""
    raise exc


def _general(key: str, payload: bytes, is_put: bool, encoding: str) -> Screened:
    """Every sample's road: each refusal with its reason."""
    if not is_put:
        return Screened(refused(key, payload, f"DELETE sample on {key}: audit events are never deleted"), None)
    if encoding.partition(";")[0] not in JSON_ENCODINGS:
        reason = f"sample on {key} declares encoding {encoding!r}: audit events are application/json"
        return Screened(refused(key, payload, reason), None)
    try:
        event, canonical = decode_event(payload)
    except EventError as exc:
        return Screened(refused(key, payload, str(exc)), _identity_of_invalid(exc, payload))
    expected = key_for(event)
    if expected != key:
        return Screened(refused(key, payload, f"key {key} does not match the event's own key {expected}"), None)
    return Screened(Candidate(key, payload, event, canonical), (event["run"], event["src"], event["seq"]))


def require_signature(item: Screened, keys: TrustedKeys) -> Screened:
    """The same item if it is refused already or its event is signed by a key trusted for its
    source; else the item refused with the reason (its identity kept: it did arrive)."""
    candidate = item.candidate
    if candidate.reason is not None:
        return item
    assert candidate.event is not None      # the store reads the event of every candidate it does not refuse
    reason = keys.reason(candidate.event)
    if reason is None:
        return item
    return Screened(refused(candidate.origin, candidate.raw, reason), item.identity)


def refused(origin: str, raw: bytes, reason: str) -> Candidate:
    """A candidate the store will quarantine with exactly these bytes and this reason."""
    return Candidate(origin, raw, reason=reason)


def _identity_of_invalid(exc: EventError, payload: bytes) -> Identity | None:
    """The identity an invalid event claims: from the store's error, or read directly if oversized."""
    if exc.run is not None and exc.src is not None and exc.seq is not None:
        return exc.run, exc.src, exc.seq
    if exc.field != "size" or len(payload) > MAX_IDENTITY_BYTES:
        return None
    try:
        event = json.loads(payload)
    except (ValueError, RecursionError):
        return None
    if not isinstance(event, dict):
        return None
    run, src, seq = event.get("run"), event.get("src"), event.get("seq")
    if isinstance(run, str) and isinstance(src, str) and type(seq) is int and seq >= 0:
        return run, src, seq
    return None
