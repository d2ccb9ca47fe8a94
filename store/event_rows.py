"""Events parsed from their rows, each checked against the columns it was read by.

A read finds rows by their columns (run, t, seq, src: the indexes) and hands back the parsed
event text. The hash chains cover the text; the columns are written from it by the append. In a
file someone has altered (a flipped bit, a rewritten row), the two can disagree, or the text may
not be an event at all: a reader that trusted it went on to a KeyError deep in the reasoner (issue
15, finding 6: random bit flips). Here each event must be a JSON object whose t, seq and src are
its row's; otherwise the read stops with EvidenceError naming the row (exit 1, as a failed
verify). The check is three comparisons an event, next to a JSON parse that costs far more.
"""
from __future__ import annotations

from typing import Any, Sequence

from . import fastjson
from .errors import EvidenceError


def events_of(rows: Sequence[tuple], run: str) -> list[dict[str, Any]]:
    """The events of rows (t, seq, src, event JSON, ...), each agreeing with its row."""
    texts = [row[3] for row in rows]
    try:
        events = fastjson.loads_all(texts)
    except ValueError:
        events = [_parsed_or_none(text) for text in texts]
    for row, event in zip(rows, events):
        if type(event) is not dict or event.get("t") != row[0] or event.get("seq") != row[1] \
                or event.get("src") != row[2]:
            raise _damaged(run, row, event)
    return events


def _parsed_or_none(text: str) -> Any:
    try:
        return fastjson.loads(text)
    except ValueError:
        return None


def _damaged(run: str, row: tuple, event: Any) -> EvidenceError:
    what = ("is not JSON" if event is None else "is not an event" if type(event) is not dict
            else "does not hold the t, seq and src its row is found by")
    return EvidenceError(f"event run={run} src={row[2]} seq={row[1]}: the stored text {what}, which no append "
                         "writes: the file was damaged or altered behind the store's back; `gaps verify` says where")
