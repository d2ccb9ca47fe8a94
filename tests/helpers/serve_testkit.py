"""`gaps serve` as a user runs it: a child process on a loopback endpoint, its stderr read as it goes.

The child's stderr is read on a thread (a full pipe would stall the service), line by line, so a test
can wait for ``serve.ready`` before it publishes and look at every log line afterwards.
"""
from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).parents[2]
GAPS = [sys.executable, "-m", "cli.main", "serve"]
PYTHON_M_INGEST = [sys.executable, "-m", "ingest"]
READY_TIMEOUT_S = 20.0


def child_env(**extra: str) -> dict[str, str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT), **extra}
    env.pop("GAPS_DB", None)
    return env


class ServeProcess:
    """One `gaps serve --db DB --listen ENDPOINT ARGS...` (or `python -m ingest ...`) child; with
    ``endpoint`` None, no --listen (the ARGS say where, e.g. --config)."""

    def __init__(self, db: Path, endpoint: str | None, *args: str, command: list[str] = GAPS,
                 env: dict[str, str] | None = None) -> None:
        where = ["--listen", endpoint] if endpoint is not None else []
        self.proc = subprocess.Popen([*command, "--db", str(db), *where, *args], cwd=ROOT,
                                     env=env or child_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True)
        self.lines: list[str] = []
        self._new: queue.Queue[str | None] = queue.Queue()
        self._out: list[str] = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self._out_reader = threading.Thread(target=lambda: self._out.append(self.proc.stdout.read()), daemon=True)
        self._out_reader.start()

    def _read(self) -> None:
        for line in self.proc.stderr:
            self.lines.append(line.rstrip("\n"))
            self._new.put(line)
        self._new.put(None)

    def wait_for_log(self, event: str, timeout: float = READY_TIMEOUT_S) -> dict:
        """The first JSON log line of ``event`` (seen before or arriving within ``timeout``)."""
        deadline = time.monotonic() + timeout
        seen = 0
        while True:
            for line in self.lines[seen:]:
                seen += 1
                record = _json_or_none(line)
                if record is not None and record.get("event") == event:
                    return record
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"no {event} from gaps serve within {timeout} s; stderr: {self.lines[-20:]}")
            try:
                if self._new.get(timeout=remaining) is None and len(self.lines) == seen:
                    raise AssertionError(f"gaps serve ended (exit {self.proc.wait()}) before {event}: {self.lines}")
            except queue.Empty:
                pass

    def stop(self, sig: int = signal.SIGTERM, timeout: float = 60.0) -> tuple[int, str]:
        """Send ``sig``, wait for the exit; (exit code, stdout)."""
        self.proc.send_signal(sig)
        return self.finish(timeout)

    def finish(self, timeout: float = 60.0) -> tuple[int, str]:
        code = self.proc.wait(timeout)
        self._reader.join(timeout)
        self._out_reader.join(timeout)
        return code, "".join(self._out)

    def records(self) -> list[dict]:
        """Every stderr line, each of which must be a JSON object (stderr is not a terminal here)."""
        return [json.loads(line) for line in self.lines]

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def _json_or_none(line: str) -> dict | None:
    try:
        record = json.loads(line)
    except ValueError:
        return None
    return record if isinstance(record, dict) else None
