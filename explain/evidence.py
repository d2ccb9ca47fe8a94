"""The evidence behind an explanation: every cited event, numbered, with its place in the hash
chain, and whether the run's chain verified.

An explanation is only as good as the record it rests on, so each fact it states points at the
event that recorded it (E1, E2, ... in the order the events happened) and the table says where each
sits in the run's tamper-evident chain. The reasoner recomputes the run's chain: if it does not verify,
the explanation says so at the top and names the first link that failed, and events from that link
on are marked as not vouched for.
"""
from __future__ import annotations

from typing import Any, Iterable, Mapping

from reasoner import ChainStatus
from store import EventRef

from .phrases import clock

# An event cited: a store.EventRef, or a proof tree's evidence, which stays DESIGN's JSON ("Proof
# trees": {run, src, seq, t, kind}) and is read as an EventRef here, at the edge.
Cite = EventRef | Mapping[str, Any]


def key(ref: Cite) -> tuple[str, int]:
    """(src, seq): the event within its run."""
    return ref.key if isinstance(ref, EventRef) else (ref["src"], ref["seq"])


def _value(ref: Cite | None) -> EventRef | None:
    """The event ref as a value; None for a proof node's evidence that names no event."""
    if isinstance(ref, EventRef):
        return ref
    return EventRef.from_json(ref) if ref and "src" in ref and "seq" in ref else None


class EvidenceIndex:
    """Numbers the events an explanation cites and looks up their chain positions."""

    def __init__(self, refs: Iterable[Cite], store: Any = None, run: str | None = None) -> None:
        unique: dict[tuple[str, int], EventRef] = {}
        for ref in refs:
            if (value := _value(ref)) is not None:
                unique.setdefault(value.key, value)
        ordered = sorted(unique.values(), key=lambda r: (r.t, r.src, r.seq))
        self.ids = {r.key: f"E{i}" for i, r in enumerate(ordered, 1)}
        self.refs = ordered
        self.positions: dict[tuple[str, int], int] = {}
        if store is not None and run is not None and hasattr(store, "chain_positions"):
            self.positions = store.chain_positions(run, list(self.ids))

    def cite(self, refs: Iterable[Cite]) -> str:
        """" [E2]" or " [E1, E4]" for these events ("" for none)."""
        ids = sorted({self.ids[key(r)] for r in refs if r and key(r) in self.ids}, key=lambda s: int(s[1:]))
        return f" [{', '.join(ids)}]" if ids else ""

    def table(self, uses: dict[tuple[str, int], list[str]], chain: ChainStatus) -> list[dict]:
        """One row per cited event: id, run, src, seq, kind, t, time, chain position, what the
        explanation used it for, and, where the run's chain failed, whether the verified part of
        it vouches for the event (those before the first link that failed)."""
        broken = chain.problem.chain_pos if chain.problem is not None else None
        rows = []
        for r in self.refs:
            pos = self.positions.get(r.key)
            row = {"id": self.ids[r.key], "run": r.run, "src": r.src, "seq": r.seq, "kind": r.kind,
                   "t": r.t, "time": clock(r.t), "chain_pos": pos, "used_for": uses.get(r.key, [])}
            if chain.failed:
                row["vouched"] = pos is not None and broken is not None and pos < broken
            rows.append(row)
        return rows


def chain_json(status: ChainStatus) -> dict:
    """{"checked", "verified", "events", "problem", "text"}: the run's chain status (the reasoner
    recomputes it, Investigation.chain) with the sentence an explanation states it in."""
    return {**status.to_json(), "text": chain_text(status)}


def chain_text(status: ChainStatus) -> str:
    """The sentence an explanation and a report state the run's chain status in."""
    if not status.checked:
        return "the hash chain was not checked (no store given)"
    if status.verified:
        return f"the run's hash chain verified: its {status.events:,} events are as recorded"
    p = status.problem
    placed = p is not None and p.chain_pos is not None
    at = f" at chain position {p.chain_pos}" if p is not None and placed else ""
    who = f" ({p.src} #{p.seq})" if p is not None and p.src is not None else ""
    after = f"; events from chain position {p.chain_pos} on are not vouched for" if p is not None and placed else ""
    what = p.what if p is not None else "a link does not match"
    return f"the run's hash chain did NOT verify: {what}{at}{who}{after}"
