"""MCAP out: a run as an indexed, compressed MCAP file that the official readers, Foxglove and
Lichtblick open, and that `gaps import` turns back into the same chain.

Layout, as DESIGN says: one channel per (src, kind) with topic = the Zenoh key expression
`gaps/<run>/<src>/<kind>`, message encoding json (the canonical envelope as stored), schema
encoding jsonschema (the envelope with the kind's body schema); log_time = publish_time = t,
sequence = seq. Metadata records come first, so that even a file cut short still says what it
should have held: `gaps.run` (run, events, span, sources, chain head, order) and one
`gaps.checkpoint` per chain checkpoint, every column as a string. Beside the events,
foxglove.SceneUpdate and foxglove.Log channels draw the run (see foxglove.py).

MCAP fields are narrower than the envelope's: log_time is unsigned, so an event before 1970 is
logged at 0; sequence is 32 bits, so seq is written modulo 2^32. The payload always holds the
exact t and seq, and import reads those.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

from mcap.writer import CompressionType, Writer

from ..db import Store
from .atomic import replacing
from .chain_check import CHECKPOINT_METADATA, RUN_METADATA
from .foxglove import DERIVED_MARK, DRAWN_KINDS, TOPICS, Derived, SceneBuilder
from .foxglove_schemas import SCENE_UPDATE, log_schema, scene_update_schema
from .foxglove_schemas import schema_bytes as foxglove_bytes
from .message_schema import schema_bytes as event_schema_bytes
from .outcomes import ExportReport
from .rows import Row, chain_head, run_summary, stored_rows

COMPRESSIONS = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
LIBRARY = "mind-the-gaps store.transfer"
_UINT32 = 1 << 32
_PROGRESS_EVERY = 10_000

Progress = Callable[[int], None]


class _Channels:
    """Registers each schema and channel the first time a message needs it."""

    def __init__(self, writer: Writer, run: str) -> None:
        self.writer, self.run = writer, run
        self.schemas: dict[str, int] = {}
        self.channels: dict[str, int] = {}

    def _schema(self, name: str, data: Callable[[], bytes]) -> int:
        if name not in self.schemas:
            self.schemas[name] = self.writer.register_schema(name=name, encoding="jsonschema", data=data())
        return self.schemas[name]

    def for_event(self, row: Row) -> int:
        topic = f"gaps/{self.run}/{row.src}/{row.kind}"
        if topic not in self.channels:
            schema_id = self._schema(row.kind, lambda: event_schema_bytes(row.kind))
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding="json", schema_id=schema_id,
                metadata={"run": self.run, "src": row.src, "kind": row.kind})
        return self.channels[topic]

    def for_derived(self, topic: str) -> int:
        if topic not in self.channels:
            name = TOPICS[topic]
            schema = scene_update_schema if name == SCENE_UPDATE else log_schema
            schema_id = self._schema(name, lambda: foxglove_bytes(schema()))
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding="json", schema_id=schema_id,
                metadata={DERIVED_MARK: "drawn from the events on export; not evidence"})
        return self.channels[topic]


def _strings(record: dict[str, Any]) -> dict[str, str]:
    """MCAP metadata values are strings; a missing value is an empty one."""
    return {key: "" if value is None else str(value) for key, value in record.items()}


def _write_metadata(writer: Writer, store: Store, run: str, order: str) -> None:
    summary = run_summary(store, run)
    writer.add_metadata(RUN_METADATA, _strings({
        "run": run, "events": summary.events, "first_t": summary.first_t, "last_t": summary.last_t,
        "sources": ",".join(summary.sources), "head": chain_head(store, run), "order": order,
        "format": "mind-the-gaps event envelope v1", "exported_by": LIBRARY,
    }))
    for checkpoint in store.checkpoints(run):
        writer.add_metadata(CHECKPOINT_METADATA, _strings(checkpoint))


def _add(writer: Writer, channel: int, t: int, data: bytes, seq: int = 0) -> None:
    log_time = max(t, 0)
    writer.add_message(channel_id=channel, log_time=log_time, publish_time=log_time, data=data,
                       sequence=seq % _UINT32)


def _draw(writer: Writer, channels: _Channels, drawn: list[Derived]) -> int:
    for item in drawn:
        data = json.dumps(item.message, separators=(",", ":"), ensure_ascii=False).encode("utf-8")
        _add(writer, channels.for_derived(item.topic), item.t, data)
    return len(drawn)


def export_mcap(
    store: Store,
    run: str,
    path: Path,
    order: str = "chain",
    progress: Progress | None = None,
    compression: str = "zstd",
    chunk_size: int = 1 << 20,
    scene: bool = True,
) -> ExportReport:
    """Write the run, its checkpoints and (unless scene=False) its drawing to `path`, replaced
    only when complete. Drawing costs most of the time of an export; a file that only carries
    events between stores (ingest to ingest) can do without it."""
    run_summary(store, run)  # an unknown run is an error before any file is created
    report = ExportReport(str(path), "mcap", run, order)
    with replacing(path) as out:
        writer = Writer(out, chunk_size=chunk_size, compression=COMPRESSIONS[compression])
        writer.start(profile="", library=LIBRARY)
        _write_metadata(writer, store, run, order)
        channels, drawing = _Channels(writer, run), SceneBuilder()
        for row in stored_rows(store, run, order):
            _add(writer, channels.for_event(row), row.t, row.text.encode("utf-8"), row.seq)
            report.events += 1
            if scene and row.kind in DRAWN_KINDS:
                report.derived += _draw(writer, channels, drawing.add(json.loads(row.text)))
            if progress is not None and report.events % _PROGRESS_EVERY == 0:
                progress(report.events)
        report.derived += _draw(writer, channels, drawing.finish())
        writer.finish()
        report.bytes = out.tell()
    if progress is not None:
        progress(report.events)
    return report
