"""What a history query asks, read from its selector: `gaps/<run>/<src>/<kind>` key expression and
the parameters `_time`, `_limit` and `_after`.

    gaps/run-1/**?_time=[2024-11-21T08:00:00Z..2024-11-21T08:05:00Z]
    gaps/**/entity.state?_time=[now(-10m)..];_limit=5000
    gaps/**?_after=run-1:99999        (the answer continues after run-1's chain position 99,999)
    gaps/run-1/**?_time=[2024-11-21T08:00:00Z%3B5m]   (Zenoh's [t;duration]: ';' separates
                                      parameters, so it is written %3B; values are percent-decoded)

Kept free of Zenoh so that it can be read and tested on its own; the queryable hands it the
selector's parts. An answer lists runs in name order and each run in chain order, so that
(run, chain position) is a cursor: an answer cut at its limit says where it stopped, and the
same query with `_after=` that cursor goes on from there.
"""
from __future__ import annotations

import re
from urllib.parse import unquote
from collections.abc import Iterable
from dataclasses import dataclass

from store import GapsError
from store.wire import HistoryFilter

from .time_range import TimeRangeError, parse_time_range

DEFAULT_LIMIT = 100_000
"""Replies a query gets when it does not say `_limit`: an answer is streamed in bounded memory
whatever its length, but a careless `gaps/**` on a store of a hundred million events should not
keep an ingest's reader busy for an hour. A longer answer is asked for page by page with `_after`."""
MAX_LIMIT = 1_000_000
PARAMETERS = ("_time", "_limit", "_after")
_CURSOR = re.compile(r"([A-Za-z0-9._-]{1,64}):(-1|\d{1,19})", re.ASCII)
_LITERAL = re.compile(r"[A-Za-z0-9._-]+", re.ASCII)


class HistoryRequestError(GapsError, ValueError):
    """A selector the history queryable cannot answer; the message is the error reply's text."""


@dataclass(frozen=True)
class HistoryRequest:
    """A parsed history query: which keys (the key expression), which times, how many replies,
    and where a paged answer resumes ((run, chain position), None: from the start)."""

    key_expr: str
    t_from: int | None = None
    t_to: int | None = None
    limit: int = DEFAULT_LIMIT
    after: tuple[str, int] | None = None

    def filter_for(self) -> HistoryFilter:
        """The store filter: the time window, and a source or a kind where the key expression
        names one without wildcards (the rest of the key is matched by Zenoh's rules, per key)."""
        chunks = self.key_expr.split("/")
        src = kind = None
        if len(chunks) == 5 and "**" not in chunks:
            if _LITERAL.fullmatch(chunks[2]) and _LITERAL.fullmatch(chunks[3]):
                src = f"{chunks[2]}/{chunks[3]}"
            if _LITERAL.fullmatch(chunks[4]):
                kind = chunks[4]
        return HistoryFilter(self.t_from, self.t_to, src, kind)


def parse_request(key_expr: str, parameters: Iterable[tuple[str, str]], now_ns: int) -> HistoryRequest:
    """The request, or a HistoryRequestError saying which parameter is wrong and how. Parameters
    starting with '_' that are not ours are Zenoh's or another tool's and are let be; any other
    is refused, so that a mistyped `time=` does not silently answer with all of history."""
    given = {name: unquote(value) for name, value in parameters}
    unknown = [name for name in given if name not in PARAMETERS and not name.startswith("_")]
    if unknown:
        raise HistoryRequestError(f"unknown parameter {unknown[0]!r} in the selector of {key_expr}: "
                                  f"a history query takes {', '.join(PARAMETERS)}")
    t_from = t_to = None
    if "_time" in given:
        try:
            t_from, t_to = parse_time_range(given["_time"], now_ns)
        except TimeRangeError as exc:
            text = str(exc)
            raise HistoryRequestError(text if text.startswith("_time=") else f"_time={given['_time']!r}: {text}") \
                from None
    return HistoryRequest(key_expr, t_from, t_to, _limit(given.get("_limit")), _after(given.get("_after")))


def _limit(text: str | None) -> int:
    if text is None:
        return DEFAULT_LIMIT
    if not text.isdigit() or not 1 <= int(text) <= MAX_LIMIT:
        raise HistoryRequestError(f"_limit={text!r}: give a whole number of replies from 1 to {MAX_LIMIT:,}")
    return int(text)


def _after(text: str | None) -> tuple[str, int] | None:
    if text is None:
        return None
    found = _CURSOR.fullmatch(text)
    if not found:
        raise HistoryRequestError(f"_after={text!r}: give the cursor an answer cut at its limit ended at, "
                                  "RUN:CHAIN_POSITION (e.g. run-1:99999)")
    return found[1], int(found[2])
