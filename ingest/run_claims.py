"""One run, one producer, at the ingest: a run the store holds is never mixed with another producer's.

A producer that publishes into a run the store already holds (a replay of another recording of run
X, a second simulation under the same --run, publishing to a running `gaps serve` that it cannot
see the store of) sends events under identities (run, src, seq) the store holds with other
content. Before, the store quarantined those as conflicting duplicates one by one, and chained the
rest (later seqs, new sources) onto the held run: two producers' events in one chain.

Here, a `run.start` that the store holds under its identity with other content (Store.first_conflict,
the check `gaps import` makes) is another producer declaring the run: it marks its run as held by
another producer, for as long as this serve runs; from then on every event of that run the writer
is given, the rest of that batch included, is quarantined with that reason and its raw bytes, never
stored. Only a run's start decides: a single conflicting duplicate of an ordinary event (a
producer's glitch, or a stranger's on an unsigned serve) is quarantined alone, as before, and the
run goes on. The same events again (a replay published twice, a producer's cache answering a
hole) and a resumed run (new seqs only) conflict with nothing and are stored or counted as
duplicates as before.

Limits: the other producer's events that reached the writer in an earlier batch than its
run.start are stored, and so are those of a producer that sends no run.start (`gaps replay` and
`gaps sim` ask the ingest first: sim_replay/held_runs.py); a restarted serve meets the contest
again only at the next conflicting run.start; and without --require-signatures anyone who can
publish can mark a run as contested with a forged run.start, as they can already quarantine its
events (docs/serve.md).
"""
from __future__ import annotations

import logging

from store import Store

from .screen import Screened, refused

log = logging.getLogger("gaps.ingest")


class RunClaims:
    """The runs this serve found held by another producer, and why."""

    def __init__(self) -> None:
        self.contested: dict[str, str] = {}

    def refuse_mixed(self, store: Store, screened: list[Screened]) -> list[Screened]:
        """The batch with each event of a contested run refused (its identity kept: it did arrive)."""
        self._find_contests(store, [item.candidate for item in screened if item.candidate.reason is None])
        if not self.contested:
            return screened
        return [self._refused(item) if self._of_contested(item) else item for item in screened]

    def _find_contests(self, store: Store, candidates: list) -> None:
        while True:
            fresh = [c for c in candidates if c.event is not None and c.event["kind"] == "run.start"
                     and c.event["run"] not in self.contested]
            conflict = store.first_conflict(fresh) if fresh else None
            if conflict is None:
                return
            run, src, seq = conflict
            self.contested[run] = (
                f"run {run} held by another producer: its run.start ({src} seq {seq}) arrived with other "
                f"content than the stored one, so this run's events are not stored by this serve (a run holds one "
                "producer's events: publish it as another run, or into another store)")
            log.warning("ingest: run %s held by another producer (its run.start, %s seq %d, differs from the "
                        "stored one): its events are quarantined, never mixed into the run", run, src, seq)

    def _of_contested(self, item: Screened) -> bool:
        event = item.candidate.event
        return item.candidate.reason is None and event is not None and event["run"] in self.contested

    def _refused(self, item: Screened) -> Screened:
        candidate = item.candidate
        assert candidate.event is not None      # only an item _of_contested is refused here
        return Screened(refused(candidate.origin, candidate.raw, self.contested[candidate.event["run"]]), item.identity)
