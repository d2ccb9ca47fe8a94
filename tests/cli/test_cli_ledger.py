"""`gaps runs`, `gaps quarantine` and `gaps verify`: tables for people, --json for programs,
exit codes for scripts, and hostile bytes shown escaped, never obeyed."""

import base64
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from store_testkit import T0, event, tamper
from typer.testing import CliRunner

from cli.main import app
from store import Store

GAPS = str(Path(sys.executable).with_name("gaps"))
HOSTILE_RAW = b'{"v": 1, "run": "\x1b[31mred[bold]big[/bold]\xff\xfe'
HOSTILE_ORIGIN = "zenoh:gaps/\x1b]0;owned\x07"


def gaps(*args, db, columns=200):
    result = CliRunner().invoke(app, [*args, "--db", str(db)], env={"COLUMNS": str(columns)})
    assert "Traceback" not in result.output
    return result


@pytest.fixture
def db(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in (0, 1, 2, 5, 6, 9)] + [event(0, kind="run.start")])
        store.append([event(1, kind="run.end", t=T0 + 3_723_500_000_000)])
        store.append([event(0, run="r2", kind="monitor.observation")])
        store.append_raw([(HOSTILE_RAW, HOSTILE_ORIGIN), (b"nonsense", "file.jsonl:3")])
    return path


def test_runs_json(db):
    result = gaps("runs", "--json", db=db)
    assert result.exit_code == 0
    r1, r2 = json.loads(result.stdout)
    assert r1 == {"run": "r1", "events": 8, "sources": ["sim/world", "vehicle/173"],
                  "first_t": T0, "last_t": T0 + 3_723_500_000_000, "start": "2024-11-21T10:15:00Z",
                  "end": "2024-11-21T11:17:03.5Z", "duration_ns": 3_723_500_000_000, "chain": "verified"}
    assert (r2["run"], r2["events"], r2["chain"]) == ("r2", 1, "verified")


def test_runs_table(db):
    result = gaps("runs", db=db)
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    header = next(line for line in lines if "run" in line and "chain" in line)
    for column in ("events", "sources", "start (UTC)", "end (UTC)", "duration"):
        assert column in header
    r1 = next(line for line in lines if "│ r1 " in line)
    for cell in ("8", "2024-11-21T10:15:00Z", "2024-11-21T11:17:03.5Z", "1:02:03.5", "verified"):
        assert cell in r1


def test_runs_with_gaps(db):
    result = gaps("runs", "--gaps", "--json", db=db)
    listed = json.loads(result.stdout)
    assert [r["run"] for r in listed["runs"]] == ["r1", "r2"]
    assert listed["gaps"] == [{"run": "r1", "src": "vehicle/173", "missing": [[3, 4], [7, 8]], "highest": 9}]
    text = gaps("runs", "--gaps", db=db).stdout
    assert "3-4, 7-8" in text and "missing seqs" in text


def test_runs_without_gaps_says_so(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(0)])
    assert "No gaps" in gaps("runs", "--gaps", db=path).stdout


def test_runs_shows_a_broken_chain(db):
    tamper(db, ("UPDATE events SET t = t + 1 WHERE run = 'r2'", ()))
    result = gaps("runs", "--json", db=db)
    assert result.exit_code == 0  # a listing, not a check: `gaps verify` is the one that fails
    assert {r["run"]: r["chain"] for r in json.loads(result.stdout)} == {"r1": "verified", "r2": "broken"}


def test_runs_without_verifying(db):
    result = gaps("runs", "--no-verify", "--json", db=db)
    assert {r["chain"] for r in json.loads(result.stdout)} == {"not checked"}


def test_an_empty_store(tmp_path):
    path = tmp_path / "gaps.db"
    Store(path).close()
    assert gaps("runs", db=path).stdout.strip() == "The store holds no runs."
    assert gaps("runs", "--json", db=path).stdout.strip() == "[]"
    assert gaps("quarantine", db=path).stdout.strip() == "Nothing was refused."


def test_quarantine_json_keeps_every_byte(db):
    result = gaps("quarantine", "--json", db=db)
    assert result.exit_code == 0
    listed = json.loads(result.stdout)
    assert (listed["total"], listed["shown"]) == (2, 2)
    hostile, nonsense = listed["items"]
    assert base64.b64decode(hostile["raw_base64"]) == HOSTILE_RAW
    assert hostile["origin"] == HOSTILE_ORIGIN
    assert "not valid UTF-8" in hostile["reason"]
    assert hostile["raw_bytes"] == len(HOSTILE_RAW)
    assert hostile["raw_preview"] == '{"v": 1, "run": "\\x1b[31mred[bold]big[/bold]\\xff\\xfe'
    assert hostile["received"].endswith("Z")
    assert nonsense["origin"] == "file.jsonl:3"


def test_quarantine_limit_shows_the_latest(db):
    listed = json.loads(gaps("quarantine", "--json", "--limit", "1", db=db).stdout)
    assert (listed["total"], listed["shown"]) == (2, 1)
    assert listed["items"][0]["origin"] == "file.jsonl:3"
    text = gaps("quarantine", "--limit", "1", db=db).stdout
    assert "Showing the latest 1 of 2 refusals" in text


def test_quarantine_table_escapes_what_it_shows(db):
    result = gaps("quarantine", db=db, columns=400)
    assert result.exit_code == 0
    assert "\x1b" not in result.stdout and "\x07" not in result.stdout
    assert "\\x1b[31mred[bold]big[/bold]\\xff\\xfe" in result.stdout  # markup shown, not applied
    assert "zenoh:gaps/\\x1b]0;owned\\x07" in result.stdout


def test_quarantine_limit_must_be_positive(db):
    result = gaps("quarantine", "--limit", "0", db=db)
    assert result.exit_code == 2


def test_verify_exit_codes(db, tmp_path):
    ok = gaps("verify", db=db)
    assert ok.exit_code == 0 and "verified" in ok.stdout
    tamper(db, ("UPDATE events SET event = replace(event, 'red light', 'red lighT') "
                "WHERE run = 'r1' AND seq = 5", ()))
    bad = gaps("verify", db=db)
    assert bad.exit_code == 1
    assert "FAILED at run r1 src vehicle/173 seq 5 (chain position 3): hash does not match" in bad.stdout
    as_json = json.loads(gaps("verify", "--json", db=db).stdout)
    assert as_json["ok"] is False and as_json["problem"]["seq"] == 5
    missing = gaps("verify", db=tmp_path / "none.db")
    assert missing.exit_code == 2 and "no event store at" in missing.output


def test_a_file_that_is_not_a_store_is_a_clear_error(tmp_path):
    junk = tmp_path / "junk.db"
    junk.write_bytes(b"this is not sqlite" * 100)
    for command in ("runs", "quarantine", "verify"):
        result = gaps(command, db=junk)
        assert result.exit_code == 2
        assert "cannot open the event store" in result.output and "file is not a database" in result.output


def test_installed_gaps_verify_draws_progress_on_stderr_only(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path, durable=False) as store:
        store.append([event(i, t=T0 + i) for i in range(40_000)])
    env = dict(os.environ, FORCE_COLOR="1", COLUMNS="100")
    result = subprocess.run([GAPS, "verify", "--json", "--db", str(path)], capture_output=True, text=True,
                            env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["ok"] is True  # stdout stays pure JSON
    assert "verifying" in result.stderr
