"""`gaps serve` run as a user runs it, a child process on a loopback endpoint: it stores what is
published, stops on SIGINT/SIGTERM only after storing everything received, refuses a second serve on
its store, comes back after kill -9, and says what it does (JSON lines, --json, systemd)."""
from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import threading
import time
from pathlib import Path

import pytest
import zenoh

from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store, StoreError
from store.wire import key_for
from tests.helpers.ingest_testkit import RUN, free_endpoint, make_event
from tests.helpers.serve_testkit import GAPS, PYTHON_M_INGEST, ROOT, ServeProcess, child_env

MATCH_S = 10.0


def events(n: int, first_seq: int = 0, sources: int = 20) -> list[dict]:
    return [make_event(f"vehicle/{i % sources}", first_seq + i // sources) for i in range(n)]


def publish(endpoint: str, batch: list[dict]) -> None:
    """Publish and wait until the ingest confirms it holds them all (received, not yet stored)."""
    with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
        assert publisher.wait_until_matched(batch[0], MATCH_S), "gaps serve never subscribed"
        publisher.publish_all(batch)
    assert publisher.confirmed_by == 1


def stored_events(db: Path) -> int:
    """The events in the store, once its chains verified."""
    with Store.open_read_only(db) as store:
        assert store.verify().ok
        return store.count()


def count_events(db: Path) -> int:
    try:
        with Store.open_read_only(db) as store:
            return store.count()
    except StoreError:   # not there yet, or its schema not yet written
        return 0


@pytest.fixture
def served(tmp_path: Path):
    """Start `gaps serve` children on tmp_path/gaps.db; whatever is left running is killed after the test."""
    started: list[ServeProcess] = []

    def start(*args: str, command: list[str] = GAPS, endpoint: str | None = None, **env: str) -> ServeProcess:
        proc = ServeProcess(tmp_path / "gaps.db", endpoint or free_endpoint(), *args, command=command,
                            env=child_env(**env))
        started.append(proc)
        return proc

    yield start
    for proc in started:
        proc.kill()


def endpoint_of(proc: ServeProcess) -> str:
    return proc.proc.args[proc.proc.args.index("--listen") + 1]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signal_stores_everything_received_then_exits_0(served, tmp_path: Path, sig: signal.Signals) -> None:
    serve = served("--json", "--status-every", "0.2")
    serve.wait_for_log("serve.ready")
    batch = events(20_000)
    publish(endpoint_of(serve), batch)   # confirmed received: in the ingest's hands, most not yet stored
    code, out = serve.stop(sig)          # at once: what is stored now is what the stop flushed
    metrics = json.loads(out)
    assert code == 0 and metrics["exit_code"] == 0, serve.lines[-5:]
    assert (metrics["received"], metrics["stored"], metrics["failed"]) == (20_000, 20_000, 0)
    assert metrics["stopped_by"] == sig.name and metrics["sources"] == 20 and metrics["gaps"] == []
    assert stored_events(tmp_path / "gaps.db") == 20_000
    assert not os.path.exists(tmp_path / "gaps.db-wal")  # closed cleanly: the journal folded back


def test_the_logs_are_json_lines_that_say_what_happened(served) -> None:
    serve = served("--status-every", "0.2")
    ready = serve.wait_for_log("serve.ready")
    assert ready["pid"] == serve.proc.pid and ready["key"] == "gaps/**" and ready["lock"].endswith("gaps.db.serve.lock")
    good = make_event("vehicle/173", 0)
    with EventPublisher(config=zenoh_config(connect=[endpoint_of(serve)])) as publisher:
        assert publisher.wait_until_matched(good, MATCH_S)
        publisher.publish(good)
        publisher.session.put(key_for(good), b'{"v": 1, "run": ', congestion_control=zenoh.CongestionControl.BLOCK)
    refused = serve.wait_for_log("serve.quarantined")
    status = serve.wait_for_log("serve.status")
    code, out = serve.stop()
    assert code == 0
    assert refused["level"] == "warning" and refused["count"] == 1
    assert refused["latest"][0]["origin"] == key_for(good) and "JSON" in refused["latest"][0]["reason"]
    assert {"events_per_s", "stored", "quarantined", "lag_s", "missing", "active_sources"} <= status.keys()
    records = serve.records()   # every line of stderr parses: nothing but JSON lines
    assert all({"ts", "level", "event"} <= r.keys() for r in records)
    assert [r["event"] for r in records if r["event"] not in ("serve.status", "serve.quarantined")] == [
        "serve.ready", "serve.stopping", "serve.stopped"]
    stopped = records[-1]
    assert (stopped["stored"], stopped["quarantined"], stopped["exit_code"]) == (1, 1, 0)
    assert out.startswith("Stopped (SIGTERM) after ") and "stored 1, duplicates 0, quarantined 1" in out
    assert "gaps quarantine --db" in out


def test_a_second_serve_on_the_same_store_is_refused(served, tmp_path: Path) -> None:
    first = served()
    first.wait_for_log("serve.ready")
    second = subprocess.run([*GAPS, "--db", str(tmp_path / "gaps.db"), "--listen", free_endpoint()], cwd=ROOT,
                            env=child_env(), capture_output=True, text=True, timeout=20)
    assert second.returncode == 4, second.stderr
    assert second.stderr.startswith("gaps: the store ") and f"gaps serve (pid {first.proc.pid}," in second.stderr
    assert "Traceback" not in second.stderr and second.stdout == ""
    publish(endpoint_of(first), events(10))   # the first one is untouched
    assert first.stop()[0] == 0 and stored_events(tmp_path / "gaps.db") == 10


def test_kill_9_leaves_no_lock_behind(served, tmp_path: Path) -> None:
    first = served()
    first.wait_for_log("serve.ready")
    publish(endpoint_of(first), events(100))
    deadline = time.monotonic() + 30
    while count_events(tmp_path / "gaps.db") < 100:   # committed, as a reader sees it
        assert time.monotonic() < deadline, "the first serve never stored the 100 events"
        time.sleep(0.05)
    first.proc.send_signal(signal.SIGKILL)
    assert first.proc.wait(30) == -signal.SIGKILL
    again = served("--json")
    again.wait_for_log("serve.ready")
    publish(endpoint_of(again), events(100, first_seq=5))
    code, out = again.stop()
    assert code == 0 and json.loads(out)["stored"] == 100
    assert stored_events(tmp_path / "gaps.db") == 200


def test_python_m_ingest_is_gaps_serve(served, tmp_path: Path) -> None:
    serve = served("--json", command=PYTHON_M_INGEST)
    serve.wait_for_log("serve.ready")
    publish(endpoint_of(serve), events(50))
    code, out = serve.stop(signal.SIGINT)
    assert code == 0 and json.loads(out)["stored"] == 50 and stored_events(tmp_path / "gaps.db") == 50
    refused = subprocess.run([*PYTHON_M_INGEST, "--db", str(tmp_path / "gaps.db"), "--key", "other/**"], cwd=ROOT,
                             env=child_env(), capture_output=True, text=True, timeout=60)
    assert refused.returncode == 2 and refused.stderr.startswith("gaps: --key 'other/**' matches no event key")


def test_systemd_hears_ready_status_and_stopping(served, tmp_path: Path) -> None:
    """The supervisor reads as systemd does, all the time (a reader thread), so that what the
    service says on its way down is there to read."""
    address = str(tmp_path / "notify.sock")
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sock:
        sock.bind(address)
        sock.settimeout(20)
        said: list[str] = []

        def listen() -> None:
            while not said or said[-1] != "STOPPING=1":
                said.append(sock.recv(4096).decode())

        reader = threading.Thread(target=listen, daemon=True)
        serve = served("--status-every", "0.1", NOTIFY_SOCKET=address)
        reader.start()
        deadline = time.monotonic() + 20
        while len(said) < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert said[0] == f"READY=1\nMAINPID={serve.proc.pid}"
        assert said[1].startswith("STATUS=0 ev/s · stored 0 ·")
        assert serve.stop()[0] == 0
        reader.join(20)
        assert said[-1] == "STOPPING=1"


def test_a_supervisor_that_stops_reading_never_holds_the_service_up(tmp_path: Path, monkeypatch) -> None:
    """A datagram socket's queue holds 10 messages by default: past that, a notification is
    dropped at once instead of waiting for a supervisor that no longer reads."""
    from ingest.sd_notify import notify
    address = str(tmp_path / "deaf.sock")
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sock:
        sock.bind(address)
        monkeypatch.setenv("NOTIFY_SOCKET", address)
        started = time.monotonic()
        taken = [notify(f"STATUS={n}") for n in range(200)]
        assert time.monotonic() - started < 5
        assert taken[0] and not taken[-1]
