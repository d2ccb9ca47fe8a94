"""The event envelope: what every event must look like before the store accepts it.

Input comes from vehicles, monitors, replays and foreign producers over the network, so every
check assumes hostile data: the answer to bad input is always an EventError saying what was wrong,
never a crash and never a silently repaired event. The body is checked against its kind's full
JSON Schema, and the source against the roles that may send the kind.
"""

from __future__ import annotations

import json
import re
from operator import itemgetter
from typing import Any, Callable

import orjson

from .body_check import body_ok, body_problem, plain_body
from .canonical import canonical_json, canonical_plain_event
from .describe import json_type as _json_type
from .describe import show as _show
from .errors import GapsError
from .kinds import KINDS, REQUIRED, SRC_ROLES
from .keys.signatures import SIG_FIELD, sig_ok, sig_problem

MAX_EVENT_BYTES = 1 << 20  # 1 MiB
ENVELOPE_FIELDS = ("v", "run", "src", "seq", "t", "kind", "body")
OPTIONAL_FIELDS = (SIG_FIELD,)  # the source's signature (store/signatures.py)
ROLES = ("vehicle", "monitor", "signal", "pedestrian", "sim")

_ID = re.compile(r"[A-Za-z0-9._-]{1,64}")
_SRC = re.compile(rf"(?:{'|'.join(ROLES)})/[A-Za-z0-9._-]{{1,64}}")
_ENVELOPE_VALUES = itemgetter(*ENVELOPE_FIELDS)
_INT64_MIN, _INT64_MAX = -(1 << 63), (1 << 63) - 1  # SQLite INTEGER range
_SIGNED_FIELDS = len(ENVELOPE_FIELDS) + 1

__all__ = [
    "ENVELOPE_FIELDS",
    "EventError",
    "OPTIONAL_FIELDS",
    "KINDS",
    "MAX_EVENT_BYTES",
    "ROLES",
    "decode_event",
    "encode_event",
    "plain_event",
    "is_source",
    "key_for",
    "parse_event",
    "validate_event",
]


class EventError(GapsError, ValueError):
    """An event was refused. The message is written for the person reading the quarantine.

    `field` names the offending part ("run", "seq", "body.facts", "json", "size", ...) so that
    callers can count refusals by cause; run, src and seq are set when the event made them known.
    """

    def __init__(
        self,
        message: str,
        *,
        field: str | None = None,
        run: str | None = None,
        src: str | None = None,
        seq: int | None = None,
    ) -> None:
        super().__init__(message)
        self.field = field
        self.run = run
        self.src = src
        self.seq = seq


# --- small predicates, shared by the checks and by the error messages -------------------------


def _is_id(value: Any) -> bool:
    return isinstance(value, str) and _ID.fullmatch(value) is not None


def _is_src(value: Any) -> bool:
    if not isinstance(value, str):
        return False
    role, _, ident = value.partition("/")
    return role in ROLES and _is_id(ident)


def is_source(value: Any) -> bool:
    """Whether a value is a valid `src` (`<role>/<id>`)."""
    return _is_src(value)


def _is_int(value: Any) -> bool:
    """JSON integers only: bool is an int subclass in Python but true/false in JSON."""
    return isinstance(value, int) and not isinstance(value, bool)


def _is_seq(value: Any) -> bool:
    return _is_int(value) and 0 <= value <= _INT64_MAX


def _error(ev: Any, field: str, problem: str) -> EventError:
    """Build an EventError prefixed with the identity of the event, as far as it is valid."""
    run = src = seq = None
    if isinstance(ev, dict):
        run = ev.get("run") if _is_id(ev.get("run")) else None
        src = ev.get("src") if _is_src(ev.get("src")) else None
        seq = ev.get("seq") if _is_seq(ev.get("seq")) else None
    parts = (("run", run), ("src", src), ("seq", seq))
    known = [f"{name}={value}" for name, value in parts if value is not None]
    where = f"event {' '.join(known)}" if known else "event"
    return EventError(f"{where}: {problem}", field=field, run=run, src=src, seq=seq)


# --- the checks, in the order a reader would want them reported -------------------------------

Problem = tuple[str, str] | None  # (field, sentence)


def _check_fields(ev: dict) -> Problem:
    missing = [name for name in ENVELOPE_FIELDS if name not in ev]
    if missing:
        return missing[0], f"missing envelope field(s) {', '.join(missing)}"
    extra = [_show(name) for name in ev if name not in ENVELOPE_FIELDS and name not in OPTIONAL_FIELDS]
    if extra:
        return "envelope", f"unknown envelope field(s) {', '.join(extra)}: extra data belongs in body"
    return None


def _check_v(ev: dict) -> Problem:
    if not (_is_int(ev["v"]) and ev["v"] == 1):
        return "v", f"v must be 1 (the envelope version), got {_show(ev['v'])}"
    return None


def _check_run(ev: dict) -> Problem:
    if not _is_id(ev["run"]):
        return "run", f"run must be 1-64 characters of A-Z a-z 0-9 . _ -, got {_show(ev['run'])}"
    return None


def _check_src(ev: dict) -> Problem:
    src = ev["src"]
    if not isinstance(src, str) or "/" not in src:
        return "src", f"src must be '<role>/<id>', got {_show(src)}"
    role, _, ident = src.partition("/")
    if role not in ROLES:
        return "src", f"src role {_show(role)} is not one of {', '.join(ROLES)}"
    if not _is_id(ident):
        return "src", f"src id must be 1-64 characters of A-Z a-z 0-9 . _ -, got {_show(ident)}"
    return None


def _check_seq(ev: dict) -> Problem:
    seq = ev["seq"]
    if not _is_int(seq):
        return "seq", f"seq must be an integer, got {_json_type(seq)} {_show(seq)}"
    if not _is_seq(seq):
        return "seq", f"seq must be between 0 and 2^63-1, got {_show(seq)}"
    return None


def _check_t(ev: dict) -> Problem:
    t = ev["t"]
    if not _is_int(t):
        return "t", f"t must be integer nanoseconds since the Unix epoch, got {_json_type(t)} {_show(t)}"
    if not _INT64_MIN <= t <= _INT64_MAX:
        return "t", f"t must fit in 64 bits, got {_show(t)}"
    return None


def _check_kind(ev: dict) -> Problem:
    if not (isinstance(ev["kind"], str) and ev["kind"] in KINDS):
        return "kind", f"kind {_show(ev['kind'])} is unknown; known kinds: {', '.join(sorted(KINDS))}"
    return None


def _check_role(ev: dict) -> Problem:
    kind, role = ev["kind"], ev["src"].partition("/")[0]
    roles = SRC_ROLES[kind]
    if role not in roles:
        return "src", f"kind {kind} comes only from src role(s) {', '.join(roles)}, not from {ev['src']}"
    return None


def _check_body(ev: dict) -> Problem:
    body, kind = ev["body"], ev["kind"]
    if not isinstance(body, dict):
        return "body", f"body must be a JSON object, got {_json_type(body)}"
    missing = [name for name in REQUIRED[kind] if name not in body]
    if missing:
        return f"body.{missing[0]}", f"body of {kind} lacks required field(s) {', '.join(missing)}"
    return body_problem(kind, body)


def _check_sig(ev: dict) -> Problem:
    if SIG_FIELD not in ev:
        return None
    problem = sig_problem(ev[SIG_FIELD])
    return None if problem is None else (SIG_FIELD, problem)


_CHECKS: tuple[Callable[[dict], Problem], ...] = (
    _check_fields,
    _check_v,
    _check_run,
    _check_src,
    _check_seq,
    _check_t,
    _check_kind,
    _check_role,
    _check_body,
    _check_sig,
)


# --- public API ---------------------------------------------------------------------------------


def validate_event(ev: dict) -> None:
    """Raise EventError for the first thing wrong with an event (as a decoded dict)."""
    if _plainly_valid(ev):
        return
    if not isinstance(ev, dict):
        raise _error(None, "event", f"must be a JSON object, got {_json_type(ev)}")
    for check in _CHECKS:
        problem = check(ev)
        if problem is not None:
            raise _error(ev, *problem)


def _plainly_valid(ev: Any) -> bool:
    """One pass over the common case, several times faster than the itemised checks (this runs
    for every event appended). It may refuse what the checks would accept (they decide then),
    but must never accept what they would refuse."""
    try:
        if type(ev) is not dict:
            return False
        if len(ev) != len(ENVELOPE_FIELDS) and not (len(ev) == _SIGNED_FIELDS and sig_ok(ev.get(SIG_FIELD))):
            return False
        v, run, src, seq, t, kind, body = _ENVELOPE_VALUES(ev)
        return (
            type(v) is int and v == 1
            and type(run) is str and (run in _SEEN_RUNS or _admit_run(run))
            and type(src) is str and type(kind) is str and ((kind, src) in _SEEN_SOURCES or _admit_source(kind, src))
            and type(seq) is int and 0 <= seq <= _INT64_MAX
            and type(t) is int and _INT64_MIN <= t <= _INT64_MAX
            and type(body) is dict
            and body_ok(kind, body)
        )
    except KeyError:
        return False


# Runs and (kind, src) pairs already found valid: a producer sends thousands of events with the
# same few, and a set lookup is cheaper than the regular expressions. Bounded against hostile
# input that makes up a new source for every event.
_SEEN_RUNS: set[str] = set()
_SEEN_SOURCES: set[tuple[str, str]] = set()
_SEEN_LIMIT = 1 << 16


def _admit_run(run: str) -> bool:
    if _ID.fullmatch(run) is None:
        return False
    _remember(_SEEN_RUNS, run)
    return True


def _admit_source(kind: str, src: str) -> bool:
    if kind not in KINDS or _SRC.fullmatch(src) is None or src.partition("/")[0] not in SRC_ROLES[kind]:
        return False
    _remember(_SEEN_SOURCES, (kind, src))
    return True


def forget_admitted() -> None:
    """Drop the runs and sources found valid (rebuilt by the next events). Called when the
    ingest goes quiet (Store.shrink_memory): a fleet's run names, up to _SEEN_LIMIT of them, would
    otherwise stay for ever, and being made in the middle of batches, scattered over the
    interpreter's memory arenas, keep those from ever being given back (4 of 34 MiB arenas after
    10,000 runs, measured with sys._debugmallocstats)."""
    _SEEN_RUNS.clear()
    _SEEN_SOURCES.clear()


def _remember(seen: set, item: Any) -> None:
    if len(seen) >= _SEEN_LIMIT:
        seen.clear()
    seen.add(item)


def encode_event(ev: dict) -> bytes:
    """Validate an event and return its canonical bytes, the form the store hashes and keeps."""
    if _plainly_valid(ev):
        data = canonical_plain_event(ev)
    else:
        validate_event(ev)
        data = None
    if data is None:
        try:
            data = canonical_json(ev)
        except (ValueError, TypeError, RecursionError) as exc:
            raise _error(ev, "body", f"cannot be written as canonical JSON: {exc}") from None
    if len(data) > MAX_EVENT_BYTES:
        problem = f"canonical form is {len(data)} bytes, over the {MAX_EVENT_BYTES}-byte limit"
        raise _error(ev, "size", problem)
    return data


def decode_event(raw: bytes) -> tuple[dict, bytes]:
    """Parse and validate raw bytes; return the event and its canonical bytes."""
    plain = plain_event(raw)
    if plain is not None:
        return plain[0], raw
    ev = _parse_json(raw)
    return ev, encode_event(ev)


PlainEvent = tuple[dict, str, str, int, str]  # (event, run, src, seq, kind)

_LOADS, _DUMPS, _SORT_KEYS = orjson.loads, orjson.dumps, orjson.OPT_SORT_KEYS


def plain_event(raw: Any) -> PlainEvent | None:
    """The event, with its run, src, seq and kind, where the bytes received are already its
    canonical form (what every producer here and any careful one sends): then a fast parser's
    reading of them is the careful one's. Whatever the careful parser refuses or reads otherwise
    cannot survive the comparison: a duplicate key, NaN, an integer beyond 64 bits (orjson reads it
    as a float), a lone surrogate or any stray whitespace makes the canonical bytes differ from the
    raw ones or fail to be written, and the careful road (decode_event's) then decides; None says
    nothing about validity. Four times cheaper where it applies (an ingest's main cost).

    What a producer sends all day long (unsigned, of a run and a (kind, src) met before, a body
    the kind's plain check takes) is judged in one expression: the ingest's writer spends most of
    its Python time per event here. Each of its tests is one the second road below makes, or
    implies one (plain_body implies body_ok and canonical's float walk over the body), so both
    accept alike (tests/store/test_store_plain_event.py holds them to the careful road)."""
    if type(raw) is not bytes or len(raw) > MAX_EVENT_BYTES:
        return None
    try:
        ev = _LOADS(raw)
    except (ValueError, RecursionError):    # orjson.JSONDecodeError is a ValueError
        return None
    try:
        if type(ev) is dict and len(ev) == len(ENVELOPE_FIELDS):
            v, run, src, seq, t, kind, body = _ENVELOPE_VALUES(ev)
            if (type(v) is int and v == 1 and type(run) is str and run in _SEEN_RUNS
                    and type(src) is str and type(kind) is str and (kind, src) in _SEEN_SOURCES
                    and type(seq) is int and 0 <= seq <= _INT64_MAX
                    and type(t) is int and _INT64_MIN <= t <= _INT64_MAX
                    and type(body) is dict and plain_body(kind)(body) and _DUMPS(ev, option=_SORT_KEYS) == raw):
                return ev, run, src, seq, kind
    except (KeyError, TypeError):  # another field set of seven; orjson.JSONEncodeError is a TypeError
        pass
    if not _plainly_valid(ev) or canonical_plain_event(ev) != raw:
        return None
    return ev, ev["run"], ev["src"], ev["seq"], ev["kind"]


def _already_canonical(raw: Any) -> dict | None:
    """plain_event's event alone."""
    plain = plain_event(raw)
    return None if plain is None else plain[0]


def parse_event(raw: bytes) -> dict:
    """Parse raw bytes (as received on Zenoh or read from a file) into a valid event."""
    return decode_event(raw)[0]


SYNC_KEY = "gaps/@ingest/sync"
"""Where every ingest answers a producer's "has all I put before this reached you?". Zenoh delivers a
query after the samples put before it on the same link, so the answer means they are in the ingest's
hands, and a producer may close its session without losing what was still on the way (a session
closed with samples queued drops them). An @ chunk: no `gaps/**` subscription or query matches it."""


def key_for(ev: dict) -> str:
    """The Zenoh key expression a (valid) event is published under."""
    return f"gaps/{ev['run']}/{ev['src']}/{ev['kind']}"


# --- JSON parsing --------------------------------------------------------------------------------


class _Refused(ValueError):
    """Raised from inside json.loads hooks; turned into an EventError by _parse_json."""


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict:
    """Refuse duplicate keys: parsers disagree on which one wins, so the event is ambiguous."""
    obj = dict(pairs)
    if len(obj) != len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:
            if key in seen:
                raise _Refused(f"duplicate key {_show(key)} in a JSON object")
            seen.add(key)
    return obj


def _no_constant(name: str) -> Any:
    raise _Refused(f"{name} is not valid JSON")


def _parse_json(raw: bytes) -> dict:
    if not isinstance(raw, (bytes, bytearray, memoryview)):
        raise TypeError(f"raw event must be bytes, got {type(raw).__name__}")
    raw = bytes(raw)
    if len(raw) > MAX_EVENT_BYTES:
        raise _error(None, "size", f"{len(raw)} bytes, over the {MAX_EVENT_BYTES}-byte limit")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise _error(None, "utf-8", f"not valid UTF-8 at byte {exc.start}: {exc.reason}") from None
    try:
        ev = json.loads(text, object_pairs_hook=_unique_keys, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        where = f"line {exc.lineno}, column {exc.colno}"
        raise _error(None, "json", f"malformed JSON at {where}: {exc.msg}") from None
    except RecursionError:
        raise _error(None, "json", "JSON nested too deeply") from None
    except ValueError as exc:  # _Refused, or an integer with too many digits
        raise _error(None, "json", f"refused JSON: {exc}") from None
    if not isinstance(ev, dict):
        raise _error(None, "event", f"must be a JSON object, got {_json_type(ev)}")
    return ev
