"""Evidence is never an output (issue 37): every command that writes a file refuses, with exit 2 and
a message naming the path and why, a file that is or resolves to the store (symlinks, `..`, hard
links), its companions (-wal, -shm, cache, serve lock), any SQLite file, or anything that is not a
regular file (a fifo, a folder, a device); the store's bytes stay as they were. Before this, `gaps
export -o X.db`, `gaps report -o X.db`, a report to a symlink to the store and `gaps regress --junit
X.db` each exited 0 over a destroyed store, and an export to a fifo or a device renamed a regular
file over it."""
from __future__ import annotations

import hashlib
import os
import stat
from pathlib import Path

import pytest

from store import OutputRefused, Store
from tests.helpers.cli import gaps

RUN = "r1"


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def hostile(db: Path, kind: str) -> Path:
    """An output path of this kind, beside the store `db` (made on disk where it must exist)."""
    folder = db.parent
    if kind == "store":
        return db
    if kind == "symlink":
        (folder / "out.link").symlink_to(db.name)
        return folder / "out.link"
    if kind == "symlink-chain":
        (folder / "a.link").symlink_to(db)
        (folder / "b.link").symlink_to("a.link")
        return folder / "b.link"
    if kind == "dotdot":
        (folder / "sub").mkdir()
        return Path(os.path.relpath(folder / "sub" / ".." / db.name))
    if kind == "hardlink":
        os.link(db, folder / "out.hard")
        return folder / "out.hard"
    if kind in ("wal", "shm", "cache", "lock"):
        suffix = {"wal": "-wal", "shm": "-shm", "cache": ".cache", "lock": ".serve.lock"}[kind]
        return folder / (db.name + suffix)
    if kind == "symlink-to-cache":
        (folder / "out.link").symlink_to(db.name + ".cache")
        return folder / "out.link"
    if kind == "other-store":
        with Store(folder / "other.db") as other:
            other.append([])
        return folder / "other.db"
    if kind == "fifo":
        os.mkfifo(folder / "out.fifo")
        return folder / "out.fifo"
    if kind == "folder":
        (folder / "out.dir").mkdir()
        return folder / "out.dir"
    raise AssertionError(kind)


KINDS = ["store", "symlink", "symlink-chain", "dotdot", "hardlink", "wal", "shm", "cache", "lock",
         "symlink-to-cache", "other-store", "fifo", "folder"]


def untouched(target: Path, kind: str, before: dict[Path, str]) -> None:
    for path, was in before.items():
        assert digest(path) == was, path
    if kind == "fifo":
        assert stat.S_ISFIFO(os.lstat(target).st_mode)
    if kind == "folder":
        assert target.is_dir() and not any(target.iterdir())
    assert not list(target.parent.glob(".*.partial"))


def refused(result, target: Path) -> None:
    assert result.exit_code == 2, result.output
    assert "refusing to write" in result.output and str(target) in result.output, result.output


def side_files(db: Path) -> dict[Path, str]:
    gaps("runs", db=db)                         # a read that leaves a cache file beside the store
    return {p: digest(p) for p in [db, db.with_name(db.name + ".cache")] if p.exists()}


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("fmt", ["jsonl", "mcap"])
def test_an_export_never_writes_over_evidence_or_a_special_file(db, kind, fmt):
    before = side_files(db)
    target = hostile(db, kind)
    result = gaps("export", "--run", RUN, "-o", target, "--format", fmt, db=db)
    refused(result, target)
    untouched(target, kind, before)


@pytest.mark.parametrize("kind", ["store", "symlink", "dotdot", "cache", "fifo", "folder"])
def test_a_report_never_writes_over_evidence_or_a_special_file(db, kind):
    before = side_files(db)
    target = hostile(db, kind)
    result = gaps("report", "--run", RUN, "-o", target, "--format", "html", db=db)
    refused(result, target)
    untouched(target, kind, before)


def test_a_report_to_a_symlink_named_html_does_not_follow_it_onto_the_store(db):
    before = side_files(db)
    (db.parent / "report.html").symlink_to(db)
    refused(gaps("report", "--run", RUN, "-o", db.parent / "report.html", db=db), db.parent / "report.html")
    untouched(db, "store", before)


@pytest.mark.parametrize("kind", ["store", "symlink", "wal"])
def test_regress_junit_never_writes_over_evidence(db, kind):
    before = side_files(db)
    target = hostile(db, kind)
    result = gaps("regress", "--run", RUN, "--junit", target, db=db)
    refused(result, target)
    untouched(target, kind, before)


@pytest.mark.parametrize("kind", ["store", "symlink", "fifo"])
def test_a_scene_picture_never_writes_over_evidence(db, kind):
    before = side_files(db)
    target = hostile(db, kind)
    refused(gaps("scene", "--run", RUN, "--at", "1s", "--svg", target, db=db), target)
    untouched(target, kind, before)


def test_public_keys_and_a_checkpoint_key_never_write_over_a_store(db, tmp_path):
    before = side_files(db)
    assert gaps("keys", "new", tmp_path / "keys", "vehicle/1").exit_code == 0
    refused(gaps("keys", "public", tmp_path / "keys", "-o", db), db)
    (tmp_path / "ck.pub").symlink_to(db)
    result = gaps("keys", "checkpoint", tmp_path / "ck")
    refused(result, tmp_path / "ck.pub")
    assert not (tmp_path / "ck").exists()          # neither half written
    untouched(db, "store", before)


@pytest.mark.skipif(os.geteuid() != 0, reason="making a device node needs root")
def test_an_export_to_a_device_leaves_the_device(db, tmp_path):
    device = tmp_path / "full"
    os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 7))       # a /dev/full of our own
    refused(gaps("export", "--run", RUN, "-o", device, "--format", "jsonl", db=db), device)
    assert stat.S_ISCHR(os.lstat(device).st_mode)


def test_an_ordinary_output_is_still_written_and_replaces_a_regular_file(db, tmp_path):
    (tmp_path / "out.jsonl").write_text("old\n")
    (tmp_path / "alias.jsonl").symlink_to("out.jsonl")
    assert gaps("export", "--run", RUN, "-o", tmp_path / "alias.jsonl", db=db).exit_code == 0
    assert (tmp_path / "alias.jsonl").is_symlink()        # the file it names was replaced, not the link
    assert (tmp_path / "out.jsonl").read_text().startswith("{")
    result = gaps("export", "--run", RUN, "-o", "-", db=db)
    assert result.exit_code == 0 and result.stdout.startswith("{")


def test_the_api_write_report_refuses_the_store(db):
    import explain
    import reasoner
    before = digest(db)
    with reasoner.open(db) as case, pytest.raises(OutputRefused, match="evidence is never an output"):
        explain.write_report(case, RUN, db.with_name(db.name + ".serve.lock"))
    assert digest(db) == before


@pytest.mark.parametrize("option", ["--truth", "--record"])
def test_a_simulation_never_writes_its_truth_or_recording_over_the_store(tmp_path, option):
    db = tmp_path / "j.db"
    with Store(db) as store:
        store.append([])
    before = digest(db)
    result = gaps("sim", "--duration", "5s", "--vehicles", "1", option, db, db=db)
    refused(result, db)
    assert digest(db) == before


@pytest.mark.parametrize("kind", ["store", "symlink", "wal", "fifo"])
def test_a_witness_file_is_never_the_store_or_a_special_file(db, tmp_path, kind):
    before = side_files(db)
    target = hostile(db, kind)
    assert gaps("keys", "checkpoint", tmp_path / "ck").exit_code == 0
    source = tmp_path / "in.jsonl"
    assert gaps("export", "--run", RUN, "-o", source, db=db).exit_code == 0
    result = gaps("import", source, "--checkpoint-key", tmp_path / "ck", "--witness", target,
                  db=tmp_path / "new.db")
    refused(result, target)
    untouched(target, kind, before)
