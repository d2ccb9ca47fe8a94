"""Where `gaps serve` says what it does: a live status line on a terminal, JSON lines otherwise.

An operator at a terminal wants one line redrawn in place and the occasional message above it; a
supervisor (systemd's journal, a container runtime, a log shipper) wants one JSON object per line that
it can filter on ``event`` and ``level`` without parsing prose. Both go to stderr: stdout is kept for
the command's result (the final metrics with ``--json``).
"""
from __future__ import annotations

import json
import logging
import threading
from datetime import datetime, timezone
from typing import Any, TextIO

from .serve_status import Status

CLEAR_LINE = "\r\x1b[2K"


class Reporter:
    """The interface; ``for_stream`` picks the implementation by whether the stream is a terminal."""

    is_terminal = False

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self._lock = threading.Lock()  # the writer thread logs too

    @staticmethod
    def for_stream(stream: TextIO) -> Reporter:
        return TerminalReporter(stream) if _is_terminal(stream) else JsonLinesReporter(stream)

    def event(self, name: str, text: str, level: str = "info", **fields: Any) -> None:
        """Something happened: ``name`` for machines, ``text`` for people, ``fields`` for both."""
        raise NotImplementedError

    def status(self, status: Status) -> None:
        """A periodic reading of the counters."""
        raise NotImplementedError

    def close(self) -> None:
        """Leave the stream clean (no half-drawn status line)."""


class JsonLinesReporter(Reporter):
    """One JSON object per line: ``{"ts", "level", "event", ...}``, ``ts`` in UTC with milliseconds."""

    def event(self, name: str, text: str, level: str = "info", **fields: Any) -> None:
        self._write({"level": level, "event": name, "message": text, **fields})

    def status(self, status: Status) -> None:
        self._write({"level": "info", "event": "serve.status", **status.to_json()})

    def _write(self, record: dict) -> None:
        line = json.dumps({"ts": _now(), **record}, ensure_ascii=False, default=str)
        with self._lock:
            self.stream.write(line + "\n")
            self.stream.flush()


class TerminalReporter(Reporter):
    """The status line redrawn in place; events printed above it as plain lines."""

    is_terminal = True

    def __init__(self, stream: TextIO) -> None:
        super().__init__(stream)
        self._line = ""

    def event(self, name: str, text: str, level: str = "info", **fields: Any) -> None:
        prefix = "" if level == "info" else f"{level}: "
        with self._lock:
            self.stream.write(f"{CLEAR_LINE}{prefix}{text}\n{self._line}")
            self.stream.flush()

    def status(self, status: Status) -> None:
        with self._lock:
            self._line = status.line()
            self.stream.write(CLEAR_LINE + self._line)
            self.stream.flush()

    def close(self) -> None:
        with self._lock:
            if self._line:
                self.stream.write(CLEAR_LINE)
                self.stream.flush()
            self._line = ""


class ReporterHandler(logging.Handler):
    """Python logging (the writer's warnings and errors) into the reporter, so nothing the ingest logs
    escapes the chosen format."""

    def __init__(self, reporter: Reporter) -> None:
        super().__init__(logging.INFO)
        self._reporter = reporter

    def emit(self, record: logging.LogRecord) -> None:
        try:
            text = record.getMessage()
            if record.exc_info and record.exc_info[1] is not None:
                text += f": {record.exc_info[1]!r}"
            self._reporter.event("log", text, record.levelname.lower(), logger=record.name)
        except Exception:
            self.handleError(record)


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")
