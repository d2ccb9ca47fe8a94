"""`gaps import` on a full disk: one line, exit 2, and the batches committed before it kept, verified
(SQLite's own full disk: PRAGMA max_page_count, from the second batch on)."""
import contextlib
import hashlib
import json
import os
import subprocess

import pytest

import store
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event


def test_import_on_a_full_disk_is_one_line_and_keeps_what_was_committed(tmp_path, monkeypatch):
    class FullAfterOneBatch(Store):
        """SQLite's own full disk (max_page_count) from the second append on."""
        def _append(self, feed):
            if getattr(self, "_full_after", False):   # a name of the test's own: Store keeps `_appended`
                pages = self.connection.execute("PRAGMA page_count").fetchone()[0]
                self.connection.execute(f"PRAGMA max_page_count = {pages}")
            self._full_after = True
            return super()._append(feed)

    source = tmp_path / "run.jsonl"
    source.write_text("".join(json.dumps(event(seq)) + "\n" for seq in range(7_000)))
    monkeypatch.setattr(store, "Store", FullAfterOneBatch)
    result = gaps("import", source, db=tmp_path / "gaps.db")
    assert result.exit_code == 2 and "database or disk is full" in result.output
    assert result.output.count("\n") == 1
    with Store.open_read_only(tmp_path / "gaps.db") as kept:
        assert kept.count() == 5_000 and kept.verify().ok


# Derived data never accuses the evidence (issue 37): with the cache file beside the store and no
# room left for it, `verify`, `runs` and `incidents` said "the file may be damaged or altered" and
# exited 1, and Store.verify raised sqlite3.OperationalError. A cache that cannot be written is
# gone without: the same results, a warning on stderr, `verify --json` saying why.

READS = (["verify"], ["runs"], ["incidents"], ["verify", "--json"], ["runs", "--json"], ["incidents", "--json"])


def _paper_store(path):
    from sim_replay.paper import paper_run
    with Store(path) as kept:
        kept.append(paper_run())
    return path


def _answers(db):
    return {tuple(args): gaps(*args, db=db) for args in READS}


def _assert_same_answers(before, after, why, warned=READS):
    """Every read as on free space (exit 0, the same output; verify's JSON but for saying why), never
    a word of damage; the reads in `warned` (those that had to write the cache) warn, saying why."""
    for args, first in before.items():
        now = after[args]
        assert now.exit_code == 0 == first.exit_code, (args, now.output)
        assert "damaged" not in now.output and "altered" not in now.output, (args, now.output)
        if args in warned and "--json" in args:     # stdout keeps its shape: the warning is a JSON line on stderr
            said = [json.loads(line) for line in now.stderr.splitlines()]
            assert [w["warning"] for w in said] == ["cache_unwritten"] and why in said[0]["why"], (args, now.stderr)
        elif args in warned:
            assert "warning: the cache could not be written" in now.stderr and why in now.stderr, (args, now.stderr)
        if args != ("verify", "--json"):
            assert now.stdout == first.stdout, args
    said = json.loads(after[("verify", "--json")].stdout)["cache"]
    assert json.loads(before[("verify", "--json")].stdout)["cache"] == {**said, "unwritten": None}
    if ("verify", "--json") in warned:
        assert why in said["unwritten"]


def test_a_cache_that_sqlite_finds_full_is_gone_without_and_never_called_damage(tmp_path, monkeypatch):
    """SQLite's own full disk for the cache file (max_page_count at its size) on every open."""
    import store.cache.file as cache_module
    db = _paper_store(tmp_path / "gaps.db")
    free = _answers(tmp_path / "gaps.db")
    fresh = _paper_store(tmp_path / "full.db")
    opened = cache_module._open

    def full(path, key):
        conn = opened(path, key)
        if conn is not None and path != cache_module.MEMORY:
            pages = conn.execute("PRAGMA page_count").fetchone()[0]
            conn.execute(f"PRAGMA max_page_count = {pages}")
        return conn
    monkeypatch.setattr(cache_module, "_open", full)
    # what fits in the pages the new file has (a verification, the runs' list) is kept; an
    # incident's measurements do not fit
    _assert_same_answers(free, _answers(fresh), "database or disk is full",
                         warned=(("incidents",), ("incidents", "--json")))
    assert db.exists()


def test_the_api_verifies_without_the_cache_when_it_cannot_be_written(tmp_path, monkeypatch):
    import store.cache.file as cache_module
    db = _paper_store(tmp_path / "gaps.db")
    opened = cache_module._open

    def full(path, key):
        conn = opened(path, key)
        if conn is not None and path != cache_module.MEMORY:
            conn.execute(f"PRAGMA max_page_count = {conn.execute('PRAGMA page_count').fetchone()[0]}")
        return conn
    monkeypatch.setattr(cache_module, "_open", full)
    with Store.open_read_only(db) as read:
        assert read.verify().ok
    with Store.open_read_only(db) as read:
        from reasoner import Case
        assert Case(read).incidents()
        assert "database or disk is full" in read.cache.unwritten


@pytest.fixture
def small_tmpfs(tmp_path):
    """A 2 MB tmpfs of our own (root only), unmounted after."""
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    where = tmp_path / "disk"
    where.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(where)], capture_output=True).returncode:
        pytest.skip("cannot mount a tmpfs here")
    yield where
    subprocess.run(["umount", "-l", str(where)], check=False)


def test_a_really_full_disk_beside_the_store_is_never_called_damage(small_tmpfs):
    """The issue's case: the cache file made beside the store, then the disk filled."""
    db = _paper_store(small_tmpfs / "gaps.db")
    free = _answers(db)
    (small_tmpfs / "gaps.db.cache").unlink()
    assert gaps("runs", db=db).exit_code == 0 and (small_tmpfs / "gaps.db.cache").stat().st_size > 0
    with contextlib.suppress(OSError), open(small_tmpfs / "filler", "wb") as filler:
        while True:
            filler.write(b"\0" * 4096)
            filler.flush()
    before = hashlib.sha256(db.read_bytes()).hexdigest()
    _assert_same_answers(free, _answers(db), "database or disk is full", warned=(("verify",), ("verify", "--json")))
    assert hashlib.sha256(db.read_bytes()).hexdigest() == before
    with Store.open_read_only(db) as read:
        assert read.verify().ok


def test_a_read_only_disk_with_the_cache_beside_the_store_reads_cleanly(small_tmpfs):
    db = _paper_store(small_tmpfs / "gaps.db")
    free = _answers(db)
    (small_tmpfs / "gaps.db.cache").unlink()
    assert gaps("runs", db=db).exit_code == 0
    assert subprocess.run(["mount", "-o", "remount,ro", str(small_tmpfs)]).returncode == 0
    after = _answers(db)
    for args, first in free.items():
        assert after[args].exit_code == 0 and "damaged" not in after[args].output, (args, after[args].output)
        assert after[args].stdout == first.stdout or args[0] == "verify"


def test_a_damaged_cache_file_is_named_as_such_never_the_evidence(tmp_path):
    """A cache file whose pages are damaged (not written by gaps: a bad disk, someone holding the
    folder) made verify and incidents say the store "may be damaged or altered", exit 1; then exit 2
    naming the cache; now the command goes on without it, naming it in a warning
    (tests/cli/test_cli_cache_unread.py has every read command)."""
    db = _paper_store(tmp_path / "gaps.db")
    cache = tmp_path / "gaps.db.cache"
    answers = {command: gaps(command, db=db).stdout for command in ("verify", "incidents")}
    assert cache.stat().st_size > 8192
    data = bytearray(cache.read_bytes())
    for at in range(4096, len(data), 97):
        data[at] ^= 0x55
    cache.write_bytes(bytes(data))
    before = hashlib.sha256(db.read_bytes()).hexdigest()
    result = gaps("incidents", db=db)
    assert result.exit_code == 0 and result.stdout == answers["incidents"], result.output
    # SQLite's own checks catch most of the flipped bytes ("could not read"); where the pages a
    # command reads keep their structure, the entries' seals catch them ("seals did not open"):
    # which one depends on where this run's entries lie, and either way the file is named
    assert f"the cache file {cache}" in result.stderr and "delete it" in result.stderr, result.stderr
    assert "could not read the cache file" in result.stderr or "seals did not open" in result.stderr
    assert "damaged or altered" not in result.output
    checked = gaps("verify", db=db)
    assert checked.exit_code == 0
    extra = [line for line in checked.stdout.splitlines() if line not in answers["verify"].splitlines()]
    assert set(answers["verify"].splitlines()) <= set(checked.stdout.splitlines()), checked.stdout
    # where the seals caught it, verify says so too (the entries are still in the file)
    assert not extra or extra[0].startswith("WARNING: the cache file beside the store holds"), extra
    assert hashlib.sha256(db.read_bytes()).hexdigest() == before


def test_cache_entries_altered_in_place_are_named_and_not_used(tmp_path):
    """Entries rewritten inside a sound SQLite file (someone holding the folder, with SQLite at
    hand) cannot carry their seals: the command computes them from the store, gives the answer it
    gave, and names the file (before, it dropped them without a word, so a damaged cache went
    unsaid whenever SQLite's own checks did not trip)."""
    import sqlite3
    db = _paper_store(tmp_path / "gaps.db")
    cache = tmp_path / "gaps.db.cache"
    first = {args: gaps(*args, db=db).stdout for args in (("incidents",), ("incidents", "--json"))}

    def alter() -> None:
        with sqlite3.connect(cache) as conn:
            assert conn.execute("UPDATE derived SET payload = payload || ' '").rowcount > 0

    alter()
    result = gaps("incidents", db=db)
    assert result.exit_code == 0 and result.stdout == first[("incidents",)], result.output
    assert f"the cache file {cache} held" in result.stderr and "seals did not open" in result.stderr, result.stderr
    assert "delete it" in result.stderr
    alter()
    result = gaps("incidents", "--json", db=db)
    assert result.exit_code == 0 and result.stdout == first[("incidents", "--json")]
    warnings = [json.loads(line) for line in result.stderr.splitlines() if line.strip()]
    assert warnings and all(w["warning"] == "cache_altered" and str(cache) in w["why"] for w in warnings), warnings
