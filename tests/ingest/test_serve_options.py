"""What `gaps serve` refuses before it receives anything, and the pieces it is made of: the store
lock, the encodings screened, the Zenoh config file, `python -m ingest` taking the same options."""
from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys

import pytest
from typer.main import get_command

from cli.main import app
from ingest.errors import StoreInUse
from ingest.screen import screen
from ingest.serve_args import parser
from ingest.serve_lock import ServeLock, lock_path
from store.wire import session_config
from store import GapsError, canonical_json
from store.wire import key_for
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import free_endpoint, make_event


def test_the_lock_refuses_a_second_holder_and_names_the_first(tmp_path) -> None:
    db = tmp_path / "gaps.db"
    with ServeLock(db):
        assert lock_path(db).read_text() == f"{os.getpid()}\n"
        with pytest.raises(StoreInUse, match=rf"already being written by a gaps serve \(pid {os.getpid()},") as err:
            ServeLock(db).acquire()
        assert isinstance(err.value, GapsError) and err.value.exit_code == 4
    with ServeLock(db):     # released on exit
        pass


def test_the_lock_dies_with_its_holder_even_on_kill_9(tmp_path) -> None:
    db = tmp_path / "gaps.db"
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from ingest.serve_lock import ServeLock; "
                               f"ServeLock({str(db)!r}).acquire(); print('held', flush=True); time.sleep(60)"],
                              stdout=subprocess.PIPE, text=True, env={**os.environ, "PYTHONPATH": os.getcwd()})
    try:
        assert holder.stdout.readline() == "held\n"
        with pytest.raises(StoreInUse, match=f"pid {holder.pid}"):
            ServeLock(db).acquire()
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
    with ServeLock(db):
        pass


@pytest.mark.parametrize("encoding", ["application/cbor", "text/plain", "image/png;x"])
def test_a_sample_declared_as_something_else_than_json_is_refused(encoding: str) -> None:
    ev = make_event("vehicle/173", 0)
    item = screen(key_for(ev), canonical_json(ev), encoding=encoding)
    assert f"declares encoding {encoding!r}" in (item.candidate.reason or "") and item.identity is None


@pytest.mark.parametrize("encoding", ["application/json", "application/json;gaps-v1", "zenoh/bytes", "text/json"])
def test_json_or_no_declared_encoding_is_judged_by_content(encoding: str) -> None:
    ev = make_event("vehicle/173", 0)
    assert screen(key_for(ev), canonical_json(ev), encoding=encoding).candidate.reason is None


def test_a_config_file_is_used_with_the_command_line_over_it(tmp_path) -> None:
    path = tmp_path / "zenoh.json5"
    path.write_text('{ mode: "client", connect: { endpoints: ["tcp/127.0.0.1:7001"] }, '
                    'scouting: { multicast: { enabled: false } } }')
    config = session_config(config_file=path)
    assert json.loads(config.get_json("mode")) == "client"
    assert json.loads(config.get_json("connect/endpoints")) == ["tcp/127.0.0.1:7001"]
    over = session_config(config_file=path, mode="peer", listen=["tcp/127.0.0.1:7002"])
    assert json.loads(over.get_json("mode")) == "peer"
    assert json.loads(over.get_json("listen/endpoints")) == ["tcp/127.0.0.1:7002"]
    assert json.loads(over.get_json("connect/endpoints")) == ["tcp/127.0.0.1:7001"]


def test_python_m_ingest_takes_the_options_of_gaps_serve() -> None:
    command = get_command(app).commands["serve"]
    typer_options = {opt for param in command.params for opt in param.opts} - {"-h", "--help"}
    argparse_options = {opt for action in parser()._actions for opt in action.option_strings} - {"-h", "--help"}
    assert typer_options == argparse_options == {"--db", "--listen", "--connect", "--mode", "--config", "--key",
                                                 "--status-every", "--require-signatures", "--checkpoint-key",
                                                 "--witness", "--publish-heads", "--json",
                                                 "--quarantine-rows", "--quarantine-bytes", "--insecure-beyond-loopback"}


def busy_endpoint() -> tuple[socket.socket, str]:
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen()
    return sock, f"tcp/127.0.0.1:{sock.getsockname()[1]}"


@pytest.mark.parametrize("args, message", [
    (["--key", "other/**"], "--key 'other/**' matches no event key: events are published under gaps/<run>/<src>/<kind>"),
    (["--key", "gaps//x"], "--key 'gaps//x' is not a Zenoh key expression: Invalid Key Expr"),
    (["--listen", "7447"], "endpoint '7447' is not of the form PROTOCOL/ADDRESS, e.g. tcp/127.0.0.1:7447"),
    (["--mode", "server"], "mode must be one of peer, client, router, not 'server'"),
    (["--config", "nowhere.json5"], "no Zenoh config file at nowhere.json5"),
    (["--listen", "BUSY"], "cannot open Zenoh (listen tcp/127.0.0.1:"),
])
def test_a_mistake_is_one_line_and_exit_2(tmp_path, args: list[str], message: str) -> None:
    sock, endpoint = busy_endpoint()
    with sock:
        result = gaps("serve", *[endpoint if a == "BUSY" else a for a in args], db=tmp_path / "gaps.db")
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(f"gaps: {message}") and result.stderr.count("\n") == 1, result.stderr
    assert " at /" not in result.stderr   # not Zenoh's Rust source location
    with ServeLock(tmp_path / "gaps.db"):  # and the lock was given back
        pass


def test_a_file_that_is_not_a_store_is_refused(tmp_path) -> None:
    db = tmp_path / "notes.txt"
    db.write_text("not a store")
    result = gaps("serve", "--listen", free_endpoint(), db=db)
    assert result.exit_code == 2 and result.stderr.startswith("gaps: ") and "notes.txt" in result.stderr
    assert db.read_text() == "not a store"
