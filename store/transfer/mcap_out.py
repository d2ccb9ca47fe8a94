"""MCAP out: a run as an indexed, compressed MCAP file that the official readers, Foxglove and
Lichtblick open, and that `gaps import` turns back into the same chain.

Layout, as DESIGN says: one channel per (src, kind) with topic = the Zenoh key expression
`gaps/<run>/<src>/<kind>`, message encoding json (the canonical envelope as stored), schema
encoding jsonschema (the envelope with the kind's body schema, in its viewer-safe form:
message_schema.py); log_time = publish_time = t, sequence = seq. Metadata records come first, so
that even a file cut short still says what it should have held: `gaps.run` (run, events, span,
sources, chain head, order) and one `gaps.checkpoint` per chain checkpoint, every column as a
string. Beside the events, foxglove.SceneUpdate and foxglove.Log channels draw the run (see
foxglove.py), in protobuf with the schemas foxglove-sdk publishes, as the SDK's own MCAP writer
writes them: Foxglove's schemas are protobuf, and the events stay the JSON they are stored as.

Every message, events and drawing alike, is written in log-time order (events by (t, seq, src)),
in chunks with their message indexes, so that viewers play the file and the official reader's
summary and indexes hold. When the run's chain order is not its time order, the chain order
follows the metadata as the `gaps.chain_order` attachment (chain_order.py), so that an import still
rebuilds the same chain.

MCAP fields are narrower than the envelope's: log_time is unsigned, so an event before 1970 is
logged at 0; sequence is 32 bits, so seq is written modulo 2^32. The payload always holds the
exact t and seq, and import reads those.
"""

from __future__ import annotations

import heapq
import json
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

from mcap.writer import CompressionType, Writer

from ..db import Store
from ..reading import one_snapshot
from . import chain_order
from .atomic import replacing
from .chain_check import CHECKPOINT_METADATA, RUN_METADATA
from .foxglove_channels import DERIVED_MARK, ENCODING, TOPICS
from .message_schema import schema_bytes as event_schema_bytes
from .outcomes import ExportReport
from .rows import Row, chain_head, chain_keys, order_of, run_summary, stored_rows
from .whole_run import WholeRun

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

    def _schema(self, name: str, encoding: str, data: Callable[[], bytes]) -> int:
        if name not in self.schemas:
            self.schemas[name] = self.writer.register_schema(name=name, encoding=encoding, data=data())
        return self.schemas[name]

    def for_event(self, row: Row) -> int:
        topic = f"gaps/{self.run}/{row.src}/{row.kind}"
        if topic not in self.channels:
            schema_id = self._schema(row.kind, "jsonschema", lambda: event_schema_bytes(row.kind))
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding="json", schema_id=schema_id,
                metadata={"run": self.run, "src": row.src, "kind": row.kind})
        return self.channels[topic]

    def for_derived(self, topic: str) -> int:
        if topic not in self.channels:
            from .foxglove import schema_data  # loads foxglove-sdk: only when drawing

            name = TOPICS[topic]
            schema_id = self._schema(name, ENCODING, lambda: schema_data(name))
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding=ENCODING, schema_id=schema_id,
                metadata={DERIVED_MARK: "drawn from the events on export; not evidence"})
        return self.channels[topic]


class _InLogTimeOrder:
    """Writes messages in log-time order. The drawing may still return a scene at the time of its
    first pending change (its horizon), so what comes after that is held back until it is drawn;
    equal log times keep the order they were given in."""

    def __init__(self, writer: Writer) -> None:
        self.writer = writer
        self._held: list[tuple[int, int, int, bytes, int]] = []
        self._given = 0

    def put(self, channel: int, t: int, data: bytes, seq: int = 0, horizon: int | None = None) -> None:
        """Hold the message, or write it at once when nothing is held and nothing drawn can precede it."""
        log_time = max(t, 0)
        if not self._held and (horizon is None or log_time <= horizon):
            self.writer.add_message(channel_id=channel, log_time=log_time, publish_time=log_time, data=data,
                                    sequence=seq % _UINT32)
            return
        self._given += 1
        heapq.heappush(self._held, (log_time, self._given, channel, data, seq % _UINT32))

    def release(self, horizon: int | None = None) -> None:
        """Write every held message, or those at or before `horizon`."""
        held = self._held
        while held and (horizon is None or held[0][0] <= horizon):
            log_time, _, channel, data, sequence = heapq.heappop(held)
            self.writer.add_message(channel_id=channel, log_time=log_time, publish_time=log_time, data=data,
                                    sequence=sequence)


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


def _chain_order(store: Store, run: str) -> bytes | None:
    """The chain-order attachment's data, or None when the chain order is the time order (the
    order the messages are written in, so an import in file order rebuilds the chain)."""
    in_time_order, previous = True, None

    def keys() -> Iterator[tuple[str, int]]:
        nonlocal in_time_order, previous
        for src, seq, t in chain_keys(store, run):
            if in_time_order and previous is not None and (t, seq, src) < previous:
                in_time_order = False
            previous = (t, seq, src)
            yield src, seq

    data = chain_order.encode(run, keys())
    return None if in_time_order else data


def _draw(out: _InLogTimeOrder, channels: _Channels, drawn: list, horizon: int | None) -> int:
    """Write the drawn messages (foxglove.Derived), returning how many."""
    for item in drawn:
        out.put(channels.for_derived(item.topic), item.t, item.data, horizon=horizon)
    return len(drawn)


class RowWriter:
    """Writes a run's rows, put in (t, seq, src) order, and (with scene) their drawing, every
    message in log-time order, counting them in the report: an export's whole run, or a
    recording's events as they come (mcap_record.py)."""

    def __init__(self, writer: Writer, run: str, report: ExportReport, progress: Progress | None = None,
                 scene: bool = True) -> None:
        self.report, self.progress = report, progress
        self.channels, self.out = _Channels(writer, run), _InLogTimeOrder(writer)
        self.drawing, self.drawn_kinds = None, frozenset[str]()
        if scene:
            from .foxglove import DRAWN_KINDS, SceneBuilder  # loads foxglove-sdk: only when drawing

            self.drawing, self.drawn_kinds = SceneBuilder(), DRAWN_KINDS

    def put(self, row: Row) -> None:
        out, drawing, report = self.out, self.drawing, self.report
        if drawing is None:  # events alone come in time order: nothing to hold back
            out.put(self.channels.for_event(row), row.t, row.text.encode("utf-8"), row.seq)
        else:
            out.put(self.channels.for_event(row), row.t, row.text.encode("utf-8"), row.seq, drawing.horizon())
            drawn = drawing.add(json.loads(row.text)) if row.kind in self.drawn_kinds else drawing.advance(row.t)
            report.derived += _draw(out, self.channels, drawn, drawing.horizon())
            out.release(drawing.horizon())
        report.events += 1
        if self.progress is not None and report.events % _PROGRESS_EVERY == 0:
            self.progress(report.events)

    def finish(self) -> None:
        if self.drawing is not None:
            self.report.derived += _draw(self.out, self.channels, self.drawing.finish(), None)
        self.out.release()


def write_rows(writer: Writer, run: str, rows: Iterable[Row], report: ExportReport, progress: Progress | None,
               scene: bool) -> None:
    """Every row of a run, given in (t, seq, src) order (RowWriter)."""
    out = RowWriter(writer, run, report, progress, scene)
    for row in rows:
        out.put(row)
    out.finish()


def _seen(rows: Iterable[Row], whole: WholeRun) -> Iterator[Row]:
    """The rows, each counted as written."""
    for row in rows:
        whole.see(row.text)
        yield row


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
    events between stores (ingest to ingest) can do without it. order="chain" lets an import
    rebuild the chain; order="time" appends the events in time order on import."""
    run_summary(store, run)  # an unknown run is an error before any file is created
    report = ExportReport(str(path), "mcap", run, order_of(order))
    with one_snapshot(store.connection), replacing(path, [store.path]) as stream:
        whole = WholeRun.of(store, run, "time")  # the events are written in time order
        writer = Writer(stream, chunk_size=chunk_size, compression=COMPRESSIONS[compression])
        writer.start(profile="", library=LIBRARY)
        _write_metadata(writer, store, run, order)
        attachment = _chain_order(store, run) if order == "chain" else None
        if attachment is not None:
            writer.add_attachment(create_time=0, log_time=0, name=chain_order.ATTACHMENT,
                                  media_type=chain_order.MEDIA_TYPE, data=attachment)
            report.chain_order = True
        write_rows(writer, run, _seen(stored_rows(store, run, "time"), whole), report, progress, scene)
        whole.check()  # before the file is finished and put in place
        writer.finish()
        report.bytes = stream.tell()
    if progress is not None:
        progress(report.events)
    return report
