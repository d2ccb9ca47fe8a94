"""On a terminal `gaps serve` draws one status line in place, and prints its messages above it."""
from __future__ import annotations

import os
import pty
import select
import signal
import subprocess
import time

from sim_replay.publisher import EventPublisher, zenoh_config
from tests.helpers.ingest_testkit import free_endpoint, make_event
from tests.helpers.serve_testkit import GAPS, ROOT, child_env


def read_until(fd: int, needle: bytes, timeout: float) -> bytes:
    """What the terminal showed, up to and including ``needle``."""
    seen = b""
    deadline = time.monotonic() + timeout
    while needle not in seen:
        remaining = deadline - time.monotonic()
        assert remaining > 0, f"{needle!r} never shown; the terminal showed {seen[-600:]!r}"
        if select.select([fd], [], [], remaining)[0]:
            try:
                seen += os.read(fd, 65536)
            except OSError:  # the child closed the terminal
                break
    return seen


def test_status_line_is_redrawn_in_place(tmp_path) -> None:
    endpoint = free_endpoint()
    parent, child = pty.openpty()
    proc = subprocess.Popen([*GAPS, "--db", str(tmp_path / "gaps.db"), "--listen", endpoint, "--status-every", "0.1"],
                            cwd=ROOT, env=child_env(), stdout=subprocess.PIPE, stderr=child, text=True)
    os.close(child)
    try:
        shown = read_until(parent, b"Ctrl-C or SIGTERM stops it", 20)
        assert b"Serving " in shown and b"listening on " + endpoint.encode() in shown and b'{"ts"' not in shown
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            batch = [make_event(f"vehicle/{i % 5}", i // 5) for i in range(500)]
            assert publisher.wait_until_matched(batch[0], 10)
            publisher.publish_all(batch)
        shown = read_until(parent, b"stored 500 \xc2\xb7", 20).decode()
        line = shown.split("\r\x1b[2K")[-1]   # each reading clears the line and redraws it
        assert "\n" not in line and " ev/s · stored 500 · dup 0 · quarantined 0 · no gaps · sources 5 active/5" in line
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
        assert proc.returncode == 0
        assert out.startswith("Stopped (SIGINT) after ") and "stored 500, duplicates 0, quarantined 0, failed 0" in out
        rest = read_until(parent, b"then closing", 10)
        time.sleep(0.2)
        while select.select([parent], [], [], 0)[0]:
            try:
                rest += os.read(parent, 65536)
            except OSError:
                break
        assert b"SIGINT: storing what was received, then closing" in rest
        assert b"Stopped (" not in rest          # the summary is said once, on stdout
        assert rest.endswith(b"\r\x1b[2K")      # and the status line is wiped, not left half-drawn
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        os.close(parent)
