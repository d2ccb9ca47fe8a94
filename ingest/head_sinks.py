"""Where the ingest publishes each signed checkpoint (a signed tree head, store/tree_heads.py)
outside the store: a witness file and/or a Zenoh key, `gaps/@heads/<run>`.

A head is published after its checkpoint is committed. Publishing cannot undo the commit, so a
sink that fails (a full disk under the witness file) is logged and counted as a writer error, the
events stay stored, and the next head published covers them (a head names the whole run up to
it); the heads lost are those of the failed publications only.
"""
from __future__ import annotations

import json
import logging
from collections.abc import Callable, Sequence

from store.keys import TreeHead, WitnessFile

log = logging.getLogger(__name__)

HEADS_PREFIX = "gaps/@heads"  # `@`: a verbatim chunk, which `gaps/**` (the events' subscription) never matches

HeadSink = Callable[[list[TreeHead]], None]


def heads_key(run: str) -> str:
    return f"{HEADS_PREFIX}/{run}"


class ZenohHeads:
    """Puts each head, as the JSON line a witness file holds, on gaps/@heads/<run>."""

    def __init__(self, session) -> None:
        self._session = session

    def __call__(self, heads: list[TreeHead]) -> None:
        if self._session.is_closed():  # the last flush, after stop: those heads reach the witness file only
            return
        for head in heads:
            payload = json.dumps(head.to_json(), sort_keys=True, separators=(",", ":"))
            self._session.put(heads_key(head.run), payload.encode("utf-8"))


class HeadSinks:
    """Every sink given, each called with every append's signed heads; a failure is reported to
    `on_error` (the writer's error count) and never ends the writer."""

    def __init__(self, sinks: Sequence[HeadSink], on_error: Callable[[str], None]) -> None:
        self._sinks = list(sinks)
        self._on_error = on_error

    def __call__(self, heads: list[TreeHead]) -> None:
        for sink in self._sinks:
            try:
                sink(heads)
            except Exception as exc:
                log.error("ingest: publishing %d signed tree heads failed: %s", len(heads), exc)
                self._on_error(f"tree heads: {exc}")


def witness_sink(path) -> WitnessFile | None:
    return None if path is None else WitnessFile(path)
