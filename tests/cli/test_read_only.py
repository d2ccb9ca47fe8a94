"""Every read command leaves the store file as it found it: the same bytes, the same mtime, and
no -wal, -shm or -journal file made beside it (derived data goes to the cache file instead)."""
import hashlib
import json

import pytest
from typer.testing import CliRunner

from cli.main import app
from sim_replay.paper import RUN, paper_run
from store import Store


def fingerprint(path):
    """The file's sha256 and mtime, and every sidecar SQLite could leave beside it."""
    sidecars = sorted(p.name for p in path.parent.iterdir() if p.name.startswith(path.name + "-"))
    return hashlib.sha256(path.read_bytes()).hexdigest(), path.stat().st_mtime_ns, sidecars


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    path = tmp_path_factory.mktemp("read-only") / "gaps.db"
    with Store(path) as store:
        store.append(paper_run())
    return path


def gaps(db, *args):
    result = CliRunner().invoke(app, [*map(str, args), "--db", str(db)], env={"COLUMNS": "200"})
    assert "Traceback" not in result.output
    assert result.exit_code == 0, (args, result.output)
    return result


def read_commands(tmp):
    return [
        ("runs",), ("runs", "--gaps", "--json"), ("verify",), ("verify", "--run", RUN), ("verify", "--snapshots"),
        ("incidents",), ("incidents", "--json"), ("incidents", "--run", RUN, "--vehicle", "173"),
        ("explain", "1", "--run", RUN), ("explain", "1", "--run", RUN, "--format", "json"),
        ("scene", "--run", RUN, "--at", "10s"), ("scene", "--run", RUN, "--at", "40.5s", "--vehicle", "253"),
        ("report", "--run", RUN, "-o", tmp / "report.html"), ("report", "--run", RUN, "-o", tmp / "report.md"),
        ("export", "--run", RUN, "-o", tmp / "run.jsonl"), ("export", "--run", RUN, "-o", tmp / "run.mcap"),
        ("quarantine",), ("quarantine", "--json"),
    ]


def test_every_read_command_leaves_the_store_file_as_it_was(db, tmp_path):
    before = fingerprint(db)
    assert before[2] == []
    for command in read_commands(tmp_path):
        gaps(db, *command)
        assert fingerprint(db) == before, command
    assert json.loads(gaps(db, "incidents", "--json").stdout)  # the commands did read the run
    assert (tmp_path / "report.html").stat().st_size > 0 and (tmp_path / "run.mcap").stat().st_size > 0


def test_the_cache_beside_it_is_safe_to_delete(db):
    first = gaps(db, "scene", "--run", RUN, "--at", "10s", "--json").stdout
    cache = db.parent / (db.name + ".cache")
    assert cache.is_file()
    cache.unlink()
    assert gaps(db, "scene", "--run", RUN, "--at", "10s", "--json").stdout == first
