"""`gaps quarantine`: what was refused, every byte kept in --json, hostile bytes shown escaped, never obeyed."""
import base64
import json

from tests.helpers.cli import HOSTILE_ORIGIN, HOSTILE_RAW, gaps


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


def test_a_file_that_is_not_a_store_is_a_clear_error(tmp_path):
    junk = tmp_path / "junk.db"
    junk.write_bytes(b"this is not sqlite" * 100)
    for command in ("runs", "quarantine", "verify"):
        result = gaps(command, db=junk)
        assert result.exit_code == 2
        assert "cannot open the event store" in result.output and "file is not a database" in result.output
