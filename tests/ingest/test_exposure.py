"""Secure by default (issue 37): a `gaps serve` that can be reached beyond loopback refuses to start
without signatures and Zenoh's authentication, unless told `--insecure-beyond-loopback`, which it
logs; what counts as beyond loopback is read from the Zenoh config it opens with; and with
signatures required, a liveliness token of a source no trusted key covers is not recorded."""
from __future__ import annotations

import io
import json
import os
import re
import shlex
import signal
import subprocess
import time
from threading import Timer
from pathlib import Path

import pytest
import zenoh

from ingest import IngestService
from ingest import exposure as exposure_module
from ingest.errors import IngestConfigError
from ingest.exposure import Exposure, check, exposure, is_loopback
from ingest.serve import ServeOptions, serve
from ingest.serve_args import parser
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from store.keys import KeyFolder, Signer, TrustedKeys
from store.wire import session_config
from tests.helpers.hardened import DOC_ROUTER_DIALED, doc_block
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, make_event
from tests.helpers.serve_testkit import GAPS, ROOT, child_env

WAIT_S = 15.0


@pytest.mark.parametrize("endpoint, loopback", [
    ("tcp/127.0.0.1:7447", True), ("tls/127.0.0.2:7447", True), ("tcp/[::1]:7447", True),
    ("udp/localhost:7447", True), ("tcp/[::ffff:127.0.0.1]:7447", True), ("unixsock-stream//tmp/z.sock", True),
    ("tcp/127.0.0.1:7447?prio=1#iface=lo", True),
    ("tcp/0.0.0.0:7447", False), ("tcp/[::]:7447", False), ("tcp/10.0.0.5:7447", False),
    ("tls/router.example.org:7447", False), ("quic/192.168.1.2:7447", False),
])
def test_an_endpoint_is_loopback_only_on_this_machine(endpoint: str, loopback: bool) -> None:
    assert is_loopback(endpoint) is loopback


def test_what_a_config_opens_is_read_from_the_config_itself(tmp_path: Path) -> None:
    assert exposure(session_config(listen=["tcp/127.0.0.1:7447"])) == Exposure((), ())
    assert exposure(session_config(listen=["tcp/0.0.0.0:7447"])).reachable == ("listens on tcp/0.0.0.0:7447",)
    assert exposure(session_config(connect=["tcp/10.0.0.5:7447"], mode="client")).reachable == (
        "connects to tcp/10.0.0.5:7447",)
    loop_file = tmp_path / "loop.json5"     # loopback endpoints, but Zenoh's scouting left on
    loop_file.write_text('{ listen: { endpoints: ["tcp/127.0.0.1:7447"] } }')
    assert exposure(session_config(config_file=loop_file)).reachable == (
        "multicast scouting is on (peer mode)", "gossip scouting is on (peer mode)")
    client = tmp_path / "client.json5"     # a client scouts for a router unless told not to
    client.write_text('{ mode: "client", connect: { endpoints: ["tcp/127.0.0.1:7447"] } }')
    assert exposure(session_config(config_file=client)).reachable == ("multicast scouting is on (client mode)",)
    served = tmp_path / "serve.json5"      # the docs' serve config as it stands there
    served.write_text(doc_block("serve.json5"))
    assert exposure(session_config(config_file=served)) == Exposure((f"connects to {DOC_ROUTER_DIALED}",),
                                                                    ("mutual TLS",))
    acl = tmp_path / "acl.json5"
    acl.write_text('{ listen: { endpoints: ["tcp/0.0.0.0:7447"] }, scouting: { multicast: { enabled: false }, '
                   'gossip: { enabled: false } }, access_control: { enabled: true, default_permission: "deny" } }')
    assert exposure(session_config(config_file=acl)).authenticated_by == ("access control (ACL)",)


def test_beyond_loopback_both_signatures_and_authentication_are_needed() -> None:
    open_ = Exposure(("listens on tcp/0.0.0.0:7447",), ())
    hardened = Exposure(("connects to tls/router.example.org:7447",), ("mutual TLS",))
    assert check(Exposure((), ()), signatures_required=False, insecure=False) == []
    assert check(hardened, signatures_required=True, insecure=False) == []
    with pytest.raises(IngestConfigError, match=r"signatures are not required .*; and its Zenoh config authenticates "
                                                r"nobody .*--insecure-beyond-loopback") as refused:
        check(open_, signatures_required=False, insecure=False)
    assert refused.value.exit_code == 2
    with pytest.raises(IngestConfigError, match="authenticates nobody"):
        check(open_, signatures_required=True, insecure=False)
    with pytest.raises(IngestConfigError, match=r"\), and signatures are not required"):
        check(hardened, signatures_required=False, insecure=False)
    assert len(check(open_, signatures_required=False, insecure=True)) == 2


def test_the_documented_systemd_unit_would_start_and_not_open(tmp_path: Path) -> None:
    """docs/serve.md's unit, its ExecStart read by `python -m ingest`'s parser, with the docs' own
    serve.json5 for its --config: reachable beyond loopback, authenticated, signatures required."""
    doc = (ROOT / "docs" / "serve.md").read_text("utf-8")
    exec_start = re.search(r"^ExecStart=\S+ serve (.*)$", doc, re.M).group(1)
    args = parser().parse_args(shlex.split(exec_start))
    assert args.config == Path("/etc/gaps/serve.json5") and args.require_signatures is not None
    assert not args.insecure_beyond_loopback and not args.listen
    served = tmp_path / "serve.json5"
    served.write_text(doc_block("serve.json5"))
    found = exposure(session_config(listen=args.listen, connect=args.connect, mode=args.mode, config_file=served))
    assert found.reachable and found.authenticated_by
    assert check(found, signatures_required=True, insecure=False) == []


def test_gaps_serve_on_every_interface_without_signatures_refuses_to_start(tmp_path: Path) -> None:
    endpoint = free_endpoint().replace("127.0.0.1", "0.0.0.0")
    db = tmp_path / "gaps.db"
    try:
        done = subprocess.run([*GAPS, "--db", str(db), "--listen", endpoint], cwd=ROOT, env=child_env(),
                              capture_output=True, text=True, timeout=30)
    except subprocess.TimeoutExpired:
        pytest.fail("gaps serve started on 0.0.0.0 without signatures")
    assert done.returncode == 2
    assert done.stderr.startswith(f"gaps: this serve can be reached beyond loopback (listens on {endpoint})")
    assert "--insecure-beyond-loopback" in done.stderr and done.stderr.count("\n") == 1
    assert not db.exists()    # refused before the store was opened


def test_the_ingest_itself_refuses_too_before_it_opens_anything(tmp_path: Path) -> None:
    """The library's IngestService, not only the command: the check is the ingest's."""
    with pytest.raises(IngestConfigError, match=r"listens on tcp/0\.0\.0\.0:"):
        IngestService(tmp_path / "gaps.db", listen=[free_endpoint().replace("127.0.0.1", "0.0.0.0")])
    assert not (tmp_path / "gaps.db").exists()


def test_the_opt_out_starts_it_and_says_so_in_the_log(tmp_path: Path, monkeypatch) -> None:
    """The serve listens on loopback here; the exposure read is made to say what a 0.0.0.0 listener's
    would (tests listen on loopback only), so that the flag's path runs whole."""
    found = Exposure(("listens on tcp/0.0.0.0:7447",), ())
    monkeypatch.setattr(exposure_module, "exposure", lambda config: found)
    options = ServeOptions(tmp_path / "gaps.db", listen=(free_endpoint(),), insecure=True, status_every_s=0.05)
    err, out = io.StringIO(), io.StringIO()
    with pytest.raises(IngestConfigError):
        serve(ServeOptions(tmp_path / "gaps.db", listen=(free_endpoint(),)), out=out, err=err)
    Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGTERM)).start()
    assert serve(options, out=out, err=err) == 0
    records = [json.loads(line) for line in err.getvalue().splitlines()]
    ready = next(r for r in records if r["event"] == "serve.ready")
    assert ready["beyond_loopback"] == ["listens on tcp/0.0.0.0:7447"] and ready["authenticated_by"] == []
    insecure = next(r for r in records if r["event"] == "serve.insecure")
    assert insecure["level"] == "warning" and len(insecure["lacks"]) == 2
    assert insecure["message"].startswith("--insecure-beyond-loopback: this serve can be reached beyond loopback")


def _changes(db: Path, src: str) -> list[bool]:
    with Store.open_read_only(db) as store:
        return [c.alive for c in store.liveliness_changes(RUN, src)]


def test_with_signatures_a_token_of_a_source_no_key_covers_is_not_recorded(tmp_path: Path) -> None:
    keys = KeyFolder(tmp_path / "keys")
    keys.create("vehicle/173")
    trusted = TrustedKeys.load(keys.write_public_keys())
    db, endpoint = tmp_path / "gaps.db", free_endpoint()
    with IngestService(db, listen=[endpoint], trusted_keys=trusted) as ingest:
        stranger = zenoh.open(zenoh_config(connect=[endpoint]))
        token = stranger.liveliness().declare_token(f"gaps/@live/{RUN}/vehicle/999")
        with EventPublisher(config=zenoh_config(connect=[endpoint]), signer=Signer(keys)) as publisher:
            first = make_event("vehicle/173", 0)
            await_match(publisher, first)
            publisher.publish(first)
            assert ingest.wait_until_stored(1, WAIT_S)
            deadline = time.monotonic() + WAIT_S
            while not _changes(db, "vehicle/173") and time.monotonic() < deadline:
                time.sleep(0.05)
        token.undeclare()
        time.sleep(0.3)
        stranger.close()
    assert _changes(db, "vehicle/173") == [True, False]      # the signed source's token: recorded
    assert _changes(db, "vehicle/999") == []                  # the stranger's: not
