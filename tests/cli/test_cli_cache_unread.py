"""A cache file that cannot be read degrades, never stops a command or accuses the evidence (issue 37).

Damaged pages, an I/O error while reading it mid-command, or a file in its place that SQLite cannot
use: every read command (runs, scene, incidents, explain, report, export, verify) answers exactly as
it does with no cache at all, exit 0, with a warning naming the cache file (a JSON line on stderr
with --json, so that stdout keeps its documented shape), and the store's bytes unchanged.
"""
import hashlib
import json
import shutil
import sqlite3

import pytest

import store.cache.file as cache_module
from sim_replay.paper import RUN, paper_run
from store import Store
from tests.helpers.cli import gaps


def _commands(out):
    return [("runs",), ("runs", "--json"), ("verify",), ("incidents",), ("incidents", "--json"),
            ("explain", "1", "--run", RUN), ("scene", "--run", RUN, "--at", "40.5s", "--json"),
            ("report", "--run", RUN, "-o", out / "report.md"), ("export", "--run", RUN, "-o", out / "run.jsonl")]


def _outputs(command):
    """What the command answered: its stdout, or the file it wrote (removed, so the next may write it)."""
    if "-o" in command and command[command.index("-o") + 1].exists():
        path = command[command.index("-o") + 1]
        text = path.read_text()
        path.unlink()
        return "\n".join(line for line in text.splitlines() if not line.startswith("Generated "))  # its time

    return None


def _answers(db, out):
    """Each read command's exit code, stdout, output file and stderr, with the store's bytes checked."""
    before = hashlib.sha256(db.read_bytes()).hexdigest()
    found = {}
    for command in _commands(out):
        result = gaps(*command, db=db)
        found[command] = (result.exit_code, result.stdout, _outputs(command), result.stderr)
        assert hashlib.sha256(db.read_bytes()).hexdigest() == before, command
    return found


@pytest.fixture
def stores(tmp_path):
    """The paper's run in one store (a report cites its store's path and sha256), twice: read first
    with no cache, then with its cache spoiled."""
    (tmp_path / "store").mkdir()
    with Store(tmp_path / "store" / "gaps.db") as kept:
        kept.append(paper_run())
    return tmp_path / "store" / "gaps.db", tmp_path / "store" / "gaps.db"


def _without_cache(db, out):
    """The answers with no cache file at all (each command finds none: it is deleted before each)."""
    answers = {}
    for command in _commands(out):
        for leftover in db.parent.glob("gaps.db.cache*"):
            leftover.unlink()
        result = gaps(*command, db=db)
        answers[command] = (result.exit_code, result.stdout, _outputs(command), result.stderr)
    return answers


def _assert_degraded(free, spoiled, cache, must_warn):
    """Every answer as without a cache (exit 0, same stdout and file), never a word of damage; the
    commands in `must_warn` name the cache file, as a JSON line when --json was given."""
    for command, (code, out, written, _) in free.items():
        now_code, now_out, now_written, err = spoiled[command]
        assert (now_code, now_out, now_written) == (code, out, written) and code == 0, (command, err)
        assert "damaged or altered" not in err and "could not read the store" not in err, (command, err)
        if command[0] in must_warn:
            assert str(cache) in err, (command, err)
            if "--json" in command:
                lines = [json.loads(line) for line in err.splitlines()]
                assert any(w["warning"] == "cache_unread" and str(cache) in w["why"] for w in lines), err
            else:
                assert f"warning: could not read the cache file {cache}" in err, (command, err)


def test_a_cache_with_damaged_pages_is_gone_without_for_every_read(stores, tmp_path):
    clean, spoiled = stores
    free = _without_cache(clean, tmp_path)
    cache = spoiled.parent / "gaps.db.cache"
    assert gaps("incidents", db=spoiled).exit_code == 0 and cache.stat().st_size > 8192
    data = bytearray(cache.read_bytes())
    for at in range(4096, len(data), 97):
        data[at] ^= 0x55
    for page in range(4096, len(data), 4096):       # every page's b-tree header too: the pages are damaged
        data[page] ^= 0xFF                          # as pages, whatever rows the flips above happen to hit
    cache.write_bytes(bytes(data))                  # (a row's payload altered alone reads as an unsealed entry,
    _assert_degraded(free, _answers(spoiled, tmp_path), cache,   # which verify rightly warns of)
                     must_warn=("incidents", "explain", "report"))


def test_a_cache_that_raises_io_errors_mid_command_is_gone_without(stores, tmp_path, monkeypatch):
    """Every read of the cache file fails with SQLite's I/O error once it is open (a failing disk)."""
    clean, spoiled = stores
    free = _without_cache(clean, tmp_path)

    class FailingReads(sqlite3.Connection):
        armed = False

        def execute(self, sql, *args):
            if self.armed and sql.lstrip().upper().startswith("SELECT"):
                raise sqlite3.OperationalError("disk I/O error")
            return super().execute(sql, *args)

    def failing(path, key):
        if path == cache_module.MEMORY:
            return opened(path, key)
        conn = sqlite3.connect(path, isolation_level=None, factory=FailingReads)
        cache_module._prepare(conn, cache_module._key_id(key))
        conn.armed = True
        return conn
    opened = cache_module._open
    monkeypatch.setattr(cache_module, "_open", failing)
    cache = spoiled.parent / "gaps.db.cache"
    _assert_degraded(free, _answers(spoiled, tmp_path), cache,
                     must_warn=("verify", "incidents", "explain", "report", "scene"))


def test_a_truncated_cache_file_is_gone_without(stores, tmp_path):
    clean, spoiled = stores
    free = _without_cache(clean, tmp_path)
    cache = spoiled.parent / "gaps.db.cache"
    assert gaps("incidents", db=spoiled).exit_code == 0
    with open(cache, "r+b") as f:
        f.truncate(cache.stat().st_size // 2)
    _assert_degraded(free, _answers(spoiled, tmp_path), cache, must_warn=("incidents",))


def test_a_folder_in_place_of_the_cache_file_is_gone_without(stores, tmp_path):
    clean, spoiled = stores
    free = _without_cache(clean, tmp_path)
    (spoiled.parent / "gaps.db.cache").mkdir()
    answers = _answers(spoiled, tmp_path)
    for command, (code, out, written, _) in free.items():
        assert answers[command][:3] == (code, out, written) and code == 0, (command, answers[command][3])
    assert (spoiled.parent / "gaps.db.cache").is_dir()
    shutil.rmtree(spoiled.parent / "gaps.db.cache")
