"""Turning what callers offer (dicts or raw bytes) into candidates for the log.

A candidate either carries a valid event with its canonical bytes, or the reason it was
refused together with the bytes to keep in quarantine, so that nothing offered is lost.
"""

from __future__ import annotations

from functools import partial
from typing import Any, NamedTuple

from .canonical import canonical_json
from .envelope import EventError, decode_event


class Candidate(NamedTuple):
    """Field order is part of the API: Candidate(origin, raw, event, canonical) for an accepted
    event, Candidate(origin, raw, reason=...) for a refused one.

    A tuple, not a dataclass: every received sample becomes one, and the ingest's common road
    builds it in C (``tuple.__new__(Candidate, (origin, raw, event, canonical, None))``, all five
    fields given) where a dataclass runs a Python ``__init__``: 0.16 us against 0.9 us an event,
    measured; and it is immutable, as a verdict should be."""

    origin: str
    raw: bytes  # what quarantine keeps if the candidate is refused
    event: dict | None = None
    canonical: bytes | None = None
    reason: str | None = None


_candidate = partial(tuple.__new__, Candidate)


def from_raw(raw: bytes, origin: str) -> Candidate:
    """A candidate from bytes as received; quarantine keeps those exact bytes. An accepted one
    is built in C, all five fields given (an import makes one for every message it reads)."""
    try:
        ev, canonical = decode_event(raw)
    except EventError as exc:
        return Candidate(origin, bytes(raw), reason=str(exc))
    return _candidate((origin, bytes(raw), ev, canonical, None))


def raw_bytes(obj: Any) -> bytes:
    """The best byte record of a refused object: canonical JSON if it has one, else its repr."""
    try:
        return canonical_json(obj)
    except (ValueError, TypeError, RecursionError):
        pass
    try:
        return repr(obj).encode("utf-8", "backslashreplace")
    except Exception:  # RecursionError, or a __repr__ that raises
        return f"<unprintable {type(obj).__name__}: nested too deeply>".encode()
