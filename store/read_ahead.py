"""Rows read by SQLite on a thread of its own while the caller works on the ones already read.

SQLite releases Python's lock while it steps through a query, so a second connection on another
thread can fetch the next rows while the caller parses the previous ones: on a long read the two
costs overlap instead of adding up. The thread stops when the rows run out, or soon after the
caller stops asking (the generator is closed or dropped).
"""
from __future__ import annotations

import queue
import sqlite3
import threading
from pathlib import Path
from typing import Any, Iterator, Sequence

_CHUNK = 1024
_QUEUED = 8           # chunks read ahead at most: memory stays bounded
_DONE = object()


def read_ahead_rows(path: str, sql: str, params: Sequence[Any]) -> Iterator[tuple]:
    """The rows of a read-only query on the store file at `path`, fetched ahead on a thread."""
    chunks: queue.Queue = queue.Queue(maxsize=_QUEUED)
    stop = threading.Event()
    worker = threading.Thread(target=_fetch, args=(path, sql, params, chunks, stop), daemon=True,
                              name="gaps-read-ahead")
    worker.start()
    try:
        while True:
            chunk = chunks.get()
            if chunk is _DONE:
                return
            if isinstance(chunk, BaseException):
                raise chunk
            yield from chunk
    finally:
        stop.set()
        while worker.is_alive():          # unblock a worker waiting to put
            try:
                chunks.get_nowait()
            except queue.Empty:
                worker.join(0.01)


def _fetch(path: str, sql: str, params: Sequence[Any], chunks: queue.Queue, stop: threading.Event) -> None:
    try:
        conn = sqlite3.connect(Path(path).absolute().as_uri() + "?mode=ro", uri=True)
        try:
            cursor = conn.execute(sql, params)
            while not stop.is_set():
                rows = cursor.fetchmany(_CHUNK)
                if not rows:
                    break
                _put(chunks, rows, stop)
        finally:
            conn.close()
        _put(chunks, _DONE, stop)
    except BaseException as exc:   # handed to the reader, raised there
        _put(chunks, exc, stop)


def _put(chunks: queue.Queue, item: Any, stop: threading.Event) -> None:
    while not stop.is_set():
        try:
            chunks.put(item, timeout=0.05)
            return
        except queue.Full:
            continue
