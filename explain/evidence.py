"""The evidence behind an explanation: every cited event, numbered, with its place in the hash
chain, and whether the run's chain verified.

An explanation is only as good as the record it rests on, so each fact it states points at the
event that recorded it (E1, E2, ... in the order the events happened) and the table says where each
sits in the run's tamper-evident chain. The reasoner recomputes the run's chain: if it does not verify,
the explanation says so at the top and names the first link that failed, and events from that link
on are marked as not vouched for.
"""
from __future__ import annotations

from typing import Any, Iterable

from reasoner import ChainStatus

from .phrases import clock


def key(ref: dict) -> tuple[str, int]:
    return (ref["src"], ref["seq"])


class EvidenceIndex:
    """Numbers the events an explanation cites and looks up their chain positions."""

    def __init__(self, refs: Iterable[dict], store: Any = None, run: str | None = None) -> None:
        unique: dict[tuple[str, int], dict] = {}
        for ref in refs:
            if ref and "src" in ref and "seq" in ref:
                unique.setdefault(key(ref), ref)
        ordered = sorted(unique.values(), key=lambda r: (r["t"], r["src"], r["seq"]))
        self.ids = {key(r): f"E{i}" for i, r in enumerate(ordered, 1)}
        self.refs = ordered
        self.positions: dict[tuple[str, int], int] = {}
        if store is not None and run is not None and hasattr(store, "chain_positions"):
            self.positions = store.chain_positions(run, list(self.ids))

    def cite(self, refs: Iterable[dict]) -> str:
        """" [E2]" or " [E1, E4]" for these events ("" for none)."""
        ids = sorted({self.ids[key(r)] for r in refs if r and key(r) in self.ids}, key=lambda s: int(s[1:]))
        return f" [{', '.join(ids)}]" if ids else ""

    def table(self, uses: dict[tuple[str, int], list[str]], problem: dict | None) -> list[dict]:
        """One row per cited event: id, run, src, seq, kind, t, time, chain position, what the
        explanation used it for, and whether the verified chain vouches for it."""
        broken = problem.get("chain_pos") if problem else None
        rows = []
        for r in self.refs:
            pos = self.positions.get(key(r))
            row = {"id": self.ids[key(r)], "run": r["run"], "src": r["src"], "seq": r["seq"], "kind": r["kind"],
                   "t": r["t"], "time": clock(r["t"]), "chain_pos": pos, "used_for": uses.get(key(r), [])}
            if problem is not None:
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
    p = status.to_json()["problem"] or {}
    at = f" at chain position {p['chain_pos']}" if p.get("chain_pos") is not None else ""
    who = f" ({p['src']} #{p['seq']})" if p.get("src") is not None else ""
    after = (f"; events from chain position {p['chain_pos']} on are not vouched for"
             if p.get("chain_pos") is not None else "")
    return f"the run's hash chain did NOT verify: {p.get('what', 'a link does not match')}{at}{who}{after}"
