"""The whole flow as a user runs it: `gaps demo` (real Zenoh on loopback, real SQLite, real
SWI-Prolog), `gaps incidents --json`, `gaps verify`, and tampering caught by `gaps verify`."""
import json
import sqlite3
import subprocess
import sys
from pathlib import Path

GAPS = str(Path(sys.executable).with_name("gaps"))


def gaps(*args, db):
    return subprocess.run([GAPS, *args, "--db", str(db)], capture_output=True, text=True, timeout=120)


def test_demo_incidents_verify_and_tamper(tmp_path):
    db = tmp_path / "gaps.db"
    demo = gaps("demo", "--paper", db=db)
    assert demo.returncode == 0, demo.stderr
    assert "stored 20" in demo.stdout
    assert "Vehicle 173 committed a punishable violation of Highway Code rule 176" in demo.stdout
    assert "Vehicle 253 committed a mitigated violation of Highway Code rule 176" in demo.stdout

    again = gaps("demo", "--paper", "--overwrite", db=db)   # idempotent: the same events are duplicates
    assert again.returncode == 0 and "duplicates 20" in again.stdout

    listed = gaps("incidents", "--json", db=db)
    assert listed.returncode == 0, listed.stderr
    found = {i["vehicle"]: i for i in json.loads(listed.stdout)}
    assert found["173"]["verdict"] == "punishable" and found["253"]["verdict"] == "mitigated"
    for key in ("id", "run", "t", "vehicle", "action", "rule", "verdict", "penalty", "liable",
                "findings", "evidence"):
        assert key in found["173"]

    ok = gaps("verify", db=db)
    assert ok.returncode == 0 and "verified" in ok.stdout

    con = sqlite3.connect(db)
    (trigger,) = [r[0] for r in con.execute(
        "select name from sqlite_master where type='trigger' and tbl_name='events' and sql like '%UPDATE%'")]
    con.execute(f'DROP TRIGGER "{trigger}"')
    con.execute("UPDATE events SET event = replace(event, '173 has red light', '173 has rad light') "
                "WHERE kind = 'monitor.observation' AND src = 'monitor/m1' AND seq = 0")
    con.commit()
    con.close()
    bad = gaps("verify", db=db)
    assert bad.returncode == 1
    assert "FAILED at run paper-junctions src monitor/m1 seq 0" in bad.stdout


def test_read_command_on_missing_store_is_a_clear_error(tmp_path):
    r = gaps("incidents", db=tmp_path / "nothing.db")
    assert r.returncode == 2
    assert "no event store at" in r.stderr and "Traceback" not in r.stderr


def test_help_loads_neither_prolog_nor_zenoh_nor_dask():
    code = ("import sys\nfrom cli.main import app\n"
            "try:\n    app(['--help'])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in ('janus_swi', 'zenoh', 'dask', 'distributed') if m in sys.modules))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.stdout.strip().endswith("[]"), r.stdout + r.stderr
    assert "demo" in r.stdout and "verify" in r.stdout
