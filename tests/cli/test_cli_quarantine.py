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


def junk_store(tmp_path):
    """A store whose quarantine holds 300 identical junk lines and one other."""
    from store import Store
    path = tmp_path / "junk.db"
    with Store(path) as store:
        store.append_raw([(b"junk", "file.jsonl:1")] * 300 + [(b"more junk", "file.jsonl:2")])
    return path


def test_identical_junk_is_listed_once_with_its_count(tmp_path):
    db = junk_store(tmp_path)
    listed = json.loads(gaps("quarantine", "--json", db=db).stdout)
    assert [(i["count"], i["origin"]) for i in listed["items"]] == [(300, "file.jsonl:1"), (1, "file.jsonl:2")]
    assert listed["held"] == {"rows": 2, "samples": 301, "bytes": 13} and listed["prunes"] == []
    assert "300" in gaps("quarantine", db=db).stdout


def test_prune_removes_the_rows_and_the_summary_stays(tmp_path):
    db = junk_store(tmp_path)
    result = gaps("quarantine", "--prune", db=db)
    assert result.exit_code == 0 and "Pruned 2 rows (301 refusals, 13 bytes" in result.stdout
    listed = json.loads(gaps("quarantine", "--json", db=db).stdout)
    assert listed["total"] == 0 and listed["held"]["rows"] == 0
    [prune] = listed["prunes"]
    assert prune["by_origin"] == {"file.jsonl": 301} and len(prune["digest"]) == 64
    text = gaps("quarantine", db=db).stdout
    assert "keeps no rows now" in text and "Pruned at" in text and "2 rows (301 refusals" in text
    assert gaps("quarantine", "--prune", db=db).stdout.strip() == "Nothing to prune."


def test_prune_before_keeps_what_is_newer(tmp_path):
    db = junk_store(tmp_path)
    result = gaps("quarantine", "--prune", "--before", "1d", "--json", db=db)
    assert result.exit_code == 0 and json.loads(result.stdout) == {"pruned": None, "rows_left": 2}


def test_prune_mistakes_are_one_line_and_exit_2(tmp_path):
    db = junk_store(tmp_path)
    for args, said in ((("--before", "1d"), "--before goes with --prune"),
                       (("--prune", "--before", "last week"), "neither a time")):
        result = gaps("quarantine", *args, db=db)
        assert result.exit_code == 2 and said in result.output
    assert gaps("quarantine", "--prune", db=tmp_path / "none.db").exit_code == 2
