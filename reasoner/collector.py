"""The cyclic collector around a judgement.

A judgement from kept measurements leaves hundreds of thousands of containers alive when it
returns (the hour's: some 470,000 proof-tree nodes, evidence and scenario tuples). With the
collector paused while judging (store.CollectorPaused), switching it back on made it run a full
pass over all of them at once, and over everything else alive: 0.6-0.9 s of a 7 s judgement, to
find nothing, since they hold no cycles and reference counting frees them when the caller drops
them.

So a judgement ends by freezing what is alive (`gc.freeze`: the collector's passes skip it;
reference counting still frees it), and the next one starts by unfreezing it and collecting
once, so that any cycle made in between is reclaimed then: memory stays bounded by what one
judgement leaves. A caller that switched the collector off is left to manage it.
"""
from __future__ import annotations

import gc


class JudgementCollector:
    """Collector paused while judging; what the judgement leaves frozen when it ends."""

    __slots__ = ("_was_enabled",)

    def __enter__(self) -> None:
        self._was_enabled = gc.isenabled()
        if self._was_enabled:
            gc.unfreeze()
            gc.collect()
        gc.disable()

    def __exit__(self, *exc: object) -> None:
        if self._was_enabled:
            gc.freeze()
            gc.enable()
