"""A run's chain order, carried beside an MCAP file's messages, and put back on import.

An MCAP file is written in log-time order (viewers and the official tools expect it; the MCAP
doctor warns at every message that goes back in time), and log_time is the event's t. A run's
hash chain covers its events in the order they were appended, which is not always time order:
events from several sources arrive interleaved. So when the two orders differ, the export writes
the chain order as an attachment before the messages (`gaps.chain_order`), and the import holds
back each event that arrives before its turn and hands the events to the store in chain order:
the re-imported run has the same chain heads.

The attachment is zlib-compressed: a JSON line {"format", "run", "events", "sources"} and then,
per event in chain order, a varint `source index * 2 + explicit`, followed by a varint seq when
`explicit` is 1; otherwise seq is the source's previous seq + 1 (its first: 0). A few bytes an
event before compression.

The import holds back at most MAX_HELD events. An event that never comes (a damaged chunk, a cut
file, a message removed) would otherwise hold back everything after it: past the bound, or at
the end of the file, what is held goes to the store in chain order with the missing ones left
out, the rest of the run follows in file order, and the chain check says the heads differ.
"""

from __future__ import annotations

import json
import zlib
from dataclasses import dataclass, field
from itertools import chain
from typing import Iterable, Iterator

from ..intake import Candidate
from .varint import read_varint

ATTACHMENT = "gaps.chain_order"
MEDIA_TYPE = "application/x-gaps-chain-order+zlib"
FORMAT = "gaps.chain_order v1"
MAX_HELD = 100_000
MAX_BYTES = 1 << 28  # decompressed: some 100 million events; a hostile attachment must not inflate further

Key = tuple[str, int]  # (src, seq)


def _varint(value: int, out: bytearray) -> None:
    while value > 0x7F:
        out.append(value & 0x7F | 0x80)
        value >>= 7
    out.append(value)


def encode(run: str, keys: Iterable[Key]) -> bytes:
    """The attachment's data for a run whose events were appended in the order of `keys`."""
    sources: dict[str, int] = {}
    last: list[int] = []
    body = bytearray()
    count = 0
    for src, seq in keys:
        index = sources.get(src)
        if index is None:
            index = sources[src] = len(sources)
            last.append(-1)
        explicit = seq != last[index] + 1
        _varint(index << 1 | explicit, body)
        if explicit:
            _varint(seq, body)
        last[index] = seq
        count += 1
    head = json.dumps({"format": FORMAT, "run": run, "events": count, "sources": list(sources)},
                      separators=(",", ":"), ensure_ascii=False).encode("utf-8")
    return zlib.compress(head + b"\n" + bytes(body), 6)


@dataclass
class ChainOrder:
    run: str
    events: int
    sources: list[str]
    body: bytes

    def keys(self) -> Iterator[Key]:
        """The run's (src, seq) in chain order, decoded as they are asked for. A one-byte varint
        (an event of one of the first 64 sources, its seq the next) is read in place: it is
        nearly every event's, and read_varint's call was most of the cost of an import's
        reordering (it runs twice: decode counts the events first)."""
        last = [-1] * len(self.sources)
        sources = self.sources
        body, pos, end = self.body, 0, len(self.body)
        while pos < end:
            value = body[pos]
            if value < 0x80:
                pos += 1
            else:
                value, pos = read_varint(body, pos)
            index = value >> 1
            if value & 1:
                seq, pos = read_varint(body, pos)
            else:
                seq = last[index] + 1
            last[index] = seq
            yield sources[index], seq


def decode(data: bytes) -> ChainOrder:
    """The chain order in an attachment's data; ValueError if it is not one this reader knows."""
    try:
        inflate = zlib.decompressobj()
        raw = inflate.decompress(data, MAX_BYTES)
        if inflate.unconsumed_tail:
            raise ValueError(f"it inflates to more than {MAX_BYTES} bytes")
        if not inflate.eof:
            raise ValueError("its compressed data ends early")
        head, _, body = raw.partition(b"\n")
        meta = json.loads(head)
        if meta.get("format") != FORMAT:
            raise ValueError(f"unknown format {meta.get('format')!r}")
        order = ChainOrder(str(meta["run"]), int(meta["events"]), [str(s) for s in meta["sources"]], body)
        count = sum(1 for _ in order.keys())  # a damaged body must fail here, not half-way through an import
    except (zlib.error, ValueError, KeyError, TypeError, IndexError) as exc:
        raise ValueError(f"not a readable chain order: {exc}") from None
    if count != order.events:
        raise ValueError(f"not a readable chain order: it lists {count} events, its header says {order.events}")
    return order


@dataclass
class _Run:
    keys: Iterator[Key]
    awaited: Key | None
    held: dict[Key, Candidate] = field(default_factory=dict)
    reordering: bool = True


class Reorder:
    """Puts the candidates of runs with a known chain order back in that order."""

    def __init__(self, max_held: int = MAX_HELD) -> None:
        self.max_held = max_held
        self._runs: dict[str, _Run] = {}
        self.abandoned: list[str] = []  # runs whose chain order could not be followed to the end

    def expect(self, order: ChainOrder) -> None:
        keys = order.keys()
        self._runs.setdefault(order.run, _Run(keys, next(keys, None)))

    def push(self, candidate: Candidate) -> list[Candidate]:
        """What may go to the store now, in order, once `candidate` has been read."""
        event = candidate.event
        if event is None:
            return [candidate]
        state = self._runs.get(event["run"])
        if state is None or not state.reordering:
            return [candidate]
        key = (event["src"], event["seq"])
        if key in state.held:  # the same event twice: the store judges the second as it comes
            return [candidate]
        state.held[key] = candidate
        out = self._release(state)
        if len(state.held) > self.max_held:
            out += self._give_up(event["run"], state)
        return out

    def finish(self) -> list[Candidate]:
        """Whatever is still held, at the end of the file."""
        out: list[Candidate] = []
        for run, state in self._runs.items():
            if state.held:
                out += self._give_up(run, state)
        return out

    @staticmethod
    def _release(state: _Run) -> list[Candidate]:
        out = []
        held, keys, awaited = state.held, state.keys, state.awaited
        while awaited is not None:
            candidate = held.pop(awaited, None)  # a Candidate is a tuple, never None
            if candidate is None:
                break
            out.append(candidate)
            awaited = next(keys, None)
        state.awaited = awaited
        return out

    def _give_up(self, run: str, state: _Run) -> list[Candidate]:
        """Hand over what is held, in chain order without the missing ones; from now on, file order."""
        out = []
        for key in chain([] if state.awaited is None else [state.awaited], state.keys):
            if not state.held:
                break
            if key in state.held:
                out.append(state.held.pop(key))
        out += state.held.values()  # events the chain order does not list, in file order
        state.held.clear()
        state.reordering, state.awaited = False, None
        self.abandoned.append(run)
        return out
