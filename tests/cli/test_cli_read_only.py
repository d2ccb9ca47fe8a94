"""Every read command leaves the store file as it found it: the same bytes, the same mtime, and
no -wal, -shm or -journal file made beside it (derived data goes to the cache file instead)."""
import hashlib
import json

from sim_replay.paper import RUN
from tests.helpers.cli import gaps


def fingerprint(path):
    """The file's sha256 and mtime, and every sidecar SQLite could leave beside it."""
    sidecars = sorted(p.name for p in path.parent.iterdir() if p.name.startswith(path.name + "-"))
    return hashlib.sha256(path.read_bytes()).hexdigest(), path.stat().st_mtime_ns, sidecars


def read(paper_db, *args):
    """A read command that must succeed."""
    result = gaps(*args, db=paper_db)
    assert result.exit_code == 0, (args, result.output)
    return result


def read_commands(tmp):
    return [
        ("runs",), ("runs", "--gaps", "--json"), ("verify",), ("verify", "--run", RUN), ("verify", "--snapshots"),
        ("incidents",), ("incidents", "--json"), ("incidents", "--run", RUN, "--vehicle", "173"),
        ("explain", "1", "--run", RUN), ("explain", "1", "--run", RUN, "--format", "json"),
        ("scene", "--run", RUN, "--at", "10s"), ("scene", "--run", RUN, "--at", "40.5s", "--vehicle", "253"),
        ("scene", "--run", RUN, "--at", "10s", "--svg", tmp / "scene.svg"),
        ("report", "--run", RUN, "-o", tmp / "report.html"), ("report", "--run", RUN, "-o", tmp / "report.md"),
        ("export", "--run", RUN, "-o", tmp / "run.jsonl"), ("export", "--run", RUN, "-o", tmp / "run.mcap"),
        ("quarantine",), ("quarantine", "--json"),
    ]


def test_every_read_command_leaves_the_store_file_as_it_was(paper_db, tmp_path):
    before = fingerprint(paper_db)
    assert before[2] == []
    for command in read_commands(tmp_path):
        read(paper_db, *command)
        assert fingerprint(paper_db) == before, command
    assert json.loads(read(paper_db, "incidents", "--json").stdout)  # the commands did read the run
    assert (tmp_path / "report.html").stat().st_size > 0 and (tmp_path / "run.mcap").stat().st_size > 0
    assert (tmp_path / "scene.svg").stat().st_size > 0


def test_the_cache_beside_it_is_safe_to_delete(paper_db):
    first = read(paper_db, "scene", "--run", RUN, "--at", "10s", "--json").stdout
    cache = paper_db.parent / (paper_db.name + ".cache")
    assert cache.is_file()
    cache.unlink()
    assert read(paper_db, "scene", "--run", RUN, "--at", "10s", "--json").stdout == first
