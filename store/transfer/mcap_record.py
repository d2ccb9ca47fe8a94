"""Recording a live stream of events as MCAP, the way a producer keeps its own log.

    with Recorder("run.mcap") as rec:        # the file appears, complete, when the block ends
        for event in events:
            rec.add(event)
    rec.report                                # ExportReport: events, drawn messages, bytes

A simulation (or a vehicle) writes what it publishes to a file of its own: the same channels,
viewer-safe schemas and drawing as `gaps export` (mcap_out.py), every message in log time. A
recording is not a chain: no store has hashed it yet, so it carries no head or checkpoints,
and `gaps import` appends it in file order (time order), checking nothing it cannot.

Events may arrive a little out of time order (a producer that stamps an event before it
publishes a later one). They are held back for `window_s` of world time and written sorted;
one that arrives later than that is still written, where it arrived, and counted in `late`
(a viewer then shows it where the file has it; nothing is dropped).
"""

from __future__ import annotations

import heapq
from pathlib import Path
from types import TracebackType
from typing import Any

from mcap.writer import Writer

from ..canonical import canonical_json
from .atomic import replacing
from .errors import TransferError
from .mcap_out import COMPRESSIONS, LIBRARY, RowWriter
from .outcomes import ExportReport
from .rows import Row

RECORDING_METADATA = "gaps.recording"
SECOND = 1_000_000_000


class Recorder:
    """Writes one run's events to an MCAP file as they come. The file replaces whatever was at
    the path only when the recorder closes without an error: a recording cut short by a crash
    never replaces a good one."""

    def __init__(self, path: str | Path, *, window_s: float = 2.0, scene: bool = True,
                 recorded_by: str = "gaps sim") -> None:
        self.path = Path(path)
        self.window = int(window_s * SECOND)
        self.scene, self.recorded_by = scene, recorded_by
        self.late = 0
        self.report: ExportReport | None = None
        self._held: list[tuple[int, int, str, int, Row]] = []
        self._n = 0
        self._newest = 0
        self._written_to: int | None = None
        self._run: str | None = None
        self._rows: RowWriter | None = None

    def __enter__(self) -> Recorder:
        self._replacing = replacing(self.path)
        self._stream = self._replacing.__enter__()
        self._writer = Writer(self._stream, chunk_size=1 << 20, compression=COMPRESSIONS["zstd"])
        self._writer.start(profile="", library=LIBRARY)
        self._report = ExportReport(str(self.path), "mcap", "", "time")
        return self

    def add(self, event: dict[str, Any]) -> None:
        """Take one event (an envelope, as published); write what the window no longer holds."""
        run, src, seq, t, kind = (event.get(k) for k in ("run", "src", "seq", "t", "kind"))
        if not (isinstance(run, str) and isinstance(src, str) and isinstance(kind, str)
                and type(seq) is int and type(t) is int):
            raise TransferError(f"not an event envelope (run, src, seq, t, kind): {str(event)[:200]}")
        if self._rows is None:
            self._start(run)
        elif run != self._run:
            raise TransferError(f"a recording holds one run: {self._run!r}, then {run!r} ({src} #{seq})")
        if self._written_to is not None and t < self._written_to:
            self.late += 1
        self._n += 1
        heapq.heappush(self._held, (t, seq, src, self._n, Row(src, seq, t, kind, canonical_json(event).decode())))
        self._newest = max(self._newest, t)
        self._write(self._newest - self.window)

    def _start(self, run: str) -> None:
        self._run = self._report.run = run
        self._writer.add_metadata(RECORDING_METADATA, {"run": run, "recorded_by": self.recorded_by, "order": "time",
                                                      "note": "a producer's recording: not yet a hash chain"})
        self._rows = RowWriter(self._writer, run, self._report, scene=self.scene)

    def _write(self, up_to: int | None) -> None:
        """Write the held rows at or before up_to (all with None), in time order."""
        held, rows = self._held, self._rows
        if rows is None:  # nothing is held before the first event starts the writer
            return
        while held and (up_to is None or held[0][0] <= up_to):
            row = heapq.heappop(held)[-1]
            self._written_to = row.t if self._written_to is None else max(self._written_to, row.t)
            rows.put(row)

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        try:
            if exc_type is None:
                if self._rows is not None:
                    self._write(None)
                    self._rows.finish()
                self._writer.finish()
                self._report.bytes = self._stream.tell()
                self.report = self._report
        finally:
            self._replacing.__exit__(exc_type, exc, tb)
