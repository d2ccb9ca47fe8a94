"""One append call's work: events chained onto their runs, refusals kept, checkpoints due.

This is the hot path of the store (every event of every vehicle passes through it), so it only
builds rows in memory; the caller writes them with executemany in one transaction. The loops
bind what they use to locals and keep the common case (a new event, the next seq of its
source) free of database queries.

Checkpoints are taken for a run after every `every`-th event of its chain, after each run.end
event, and at the end of the call if the run's chain grew past its latest checkpoint, so that
every stored event is covered by a checkpoint once the call returns: an event added to the file
later, by anyone else, then stands out as uncovered.
"""

from __future__ import annotations

from typing import Iterable, cast

from . import merkle
from .canonical import canonical_json
from .chain import RunChain
from .envelope import EventError, encode_event
from .heads import Heads
from .intake import Candidate, raw_bytes
from .outcomes import AppendReport, Rejection
from .keys.tree_heads import CheckpointKey, TreeHead
from .wire.ends import WireEnd, to_part


class Batch:
    """Rows for the events, quarantine and checkpoints tables, and the report of the call."""

    def __init__(self, heads: Heads, every: int, received_at: int, key: CheckpointKey | None = None,
                 wire: tuple[WireEnd, ...] | None = None) -> None:
        self.heads = heads
        self.key = key
        self.wire = wire  # the wire tables' ends, which every checkpoint of the call records (store/wire_ends.py)
        self._wire_text = None if wire is None else canonical_json(to_part(wire)).decode()
        self.signed: list[TreeHead] = []  # the checkpoints' tree heads, signed (with a key)
        self._max_seq = heads.max_seq
        self.every = every
        self.received_at = received_at
        self.events: list[tuple] = []  # (run, chain_pos, src, seq, t, kind, event, hash)
        self.refused: list[tuple] = []  # (received_at, origin, reason, raw)
        self.checkpoints: list[tuple] = []  # (run, count, head, created_at, merkle_root, frontier, prev_count,
        #                                      signature, key_id, wire)
        self.report = AppendReport()
        self._grown: dict[str, RunChain] = {}  # runs this call extended
        self._placed: dict[tuple[str, str, int], str] | None = None  # built only if a seq repeats
        self.ended: dict[str, None] = {}  # runs whose run.end this call stored, in order

    # --- feeding ---------------------------------------------------------------------------------

    def offer_events(self, events: Iterable[dict], origin: str) -> None:
        """Validate, encode and place decoded events, all from `origin`."""
        place, refuse = self._place, self._refuse
        for ev in events:
            try:
                canonical = encode_event(ev)
            except EventError as exc:
                refuse(origin, raw_bytes(ev), str(exc))
                continue
            reason = place(ev, canonical)
            if reason is not None:
                refuse(origin, canonical, reason)

    def offer_candidates(self, candidates: Iterable[Candidate]) -> None:
        """Place candidates judged already (accepted ones are trusted as built)."""
        place, refuse = self._place, self._refuse
        for origin, raw, event, canonical, reason in candidates:
            if reason is None:
                reason = place(cast(dict, event), cast(bytes, canonical))  # accepted: both given
            if reason is not None:
                refuse(origin, raw, reason)

    def finish(self) -> None:
        """Checkpoint every run this call extended beyond its latest checkpoint."""
        for run, chain in self._grown.items():
            if chain.checkpointed != chain.count:
                self._checkpoint(run, chain)
        self.report.stored = len(self.events)
        self.report.ended = tuple(self.ended)

    # --- placing ---------------------------------------------------------------------------------

    def _refuse(self, origin: str, raw: bytes, reason: str) -> None:
        self.refused.append((self.received_at, origin, reason, raw))
        self.report.rejected.append(Rejection(origin, reason))

    def _place(self, ev: dict, canonical: bytes) -> str | None:
        """Chain a valid event onto its run, or count it as a duplicate; return a reason to
        refuse it if it conflicts with an event already stored under its (run, src, seq)."""
        run, src, seq, kind = ev["run"], ev["src"], ev["seq"], ev["kind"]
        source = (run, src)
        max_seq = self._max_seq
        highest = max_seq.get(source)
        if highest is None:
            highest = self.heads.highest_seq(run, src)
        if seq <= highest:
            earlier = self._earlier(run, src, seq)
            if earlier is not None:
                return self._duplicate(run, src, seq, earlier, canonical)
        else:
            max_seq[source] = seq
        chain = self._grown.get(run) or self._grow(run)
        position = chain.count
        digest = chain.extend(canonical)
        text = canonical.decode()
        self.events.append((run, position, src, seq, ev["t"], kind, text, digest.hex()))
        if self._placed is not None:
            self._placed[(run, src, seq)] = text
        if chain.count % self.every == 0 or kind == "run.end":
            self._checkpoint(run, chain)
        if kind == "run.end":
            self.ended[run] = None
        return None

    def _earlier(self, run: str, src: str, seq: int) -> bytes | None:
        """The event already placed by this call or stored under this identity, if any."""
        if self._placed is None:  # first repeat in this call: index what was placed so far
            self._placed = {(row[0], row[2], row[3]): row[6] for row in self.events}
        text = self._placed.get((run, src, seq))
        if text is not None:
            return text.encode()
        return self.heads.stored_event(run, src, seq)

    def _duplicate(self, run: str, src: str, seq: int, earlier: bytes, canonical: bytes) -> str | None:
        if earlier != canonical:
            return f"conflicting duplicate of {run}/{src}/{seq}"
        self.report.duplicates += 1
        return None

    @property
    def grown(self) -> dict[str, RunChain]:
        """The runs this call extended, each with its chain as it now ends."""
        return self._grown

    def _grow(self, run: str) -> RunChain:
        chain = self._grown[run] = self.heads.chain(run)
        return chain

    def _checkpoint(self, run: str, chain: RunChain) -> None:
        """A checkpoint row at the chain's end, signed with the checkpoint key if there is one
        (one signature per checkpoint: every 1,000 events and once per call and run)."""
        head = TreeHead(run, chain.count, chain.root().hex(), chain.head.hex(), chain.checkpointed, self.received_at,
                        wire=self.wire)
        if self.key is not None:
            head = self.key.sign(head)
            self.signed.append(head)
        self.checkpoints.append((run, head.size, head.head, head.created_at, head.root, merkle.pack(chain.frontier),
                                 head.prev_size, head.sig, head.key, self._wire_text))
        chain.checkpointed = chain.count
