"""Output paths fuzzed (issue 37): any command that writes a file, given a hostile path - the store
itself or one of its companions (-wal, -shm, cache, serve lock), another store, a fifo, a folder, a
device (as root) - reached any way (absolute, relative, through `..`, a symlink, a chain of them, a
symlinked folder, a hard link), ends with exit 2 and a message naming the path, and leaves the
evidence byte for byte as it was and the special file what it was."""
from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import stat
import tempfile
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim_replay.paper import RUN, paper_run
from store import Store
from tests.fuzz.budget import fuzz
from tests.helpers.cli import gaps

TARGETS = ["store", "wal", "shm", "journal", "cache", "lock", "other-store", "fifo", "folder"] + (
    ["device"] if os.geteuid() == 0 else [])
FORMS = ["absolute", "relative", "dotdot", "symlink", "symlink-chain", "symlinked-folder", "hardlink"]
COMMANDS = {
    "export-jsonl": lambda out: ["export", "--run", RUN, "--format", "jsonl", "-o", out],
    "export-mcap": lambda out: ["export", "--run", RUN, "--format", "mcap", "-o", out],
    "report-html": lambda out: ["report", "--run", RUN, "--format", "html", "-o", out],
    "report-json": lambda out: ["report", "--run", RUN, "--format", "json", "-o", out],
    "scene-svg": lambda out: ["scene", "--run", RUN, "--at", "10s", "--svg", out],
}


@pytest.fixture(scope="module")
def original(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("fuzz-outputs") / "gaps.db"
    with Store(path) as store:
        store.append(paper_run())
    gaps("incidents", db=path)           # its cache file beside it, as after any reading
    return path


def _target(folder: Path, db: Path, target: str) -> Path:
    names = {"wal": "-wal", "shm": "-shm", "journal": "-journal", "cache": ".cache", "lock": ".serve.lock"}
    if target == "store":
        return db
    if target in names:
        path = folder / (db.name + names[target])
        if target in ("lock", "wal") and not path.exists():
            path.write_bytes(b"\0" * 32)        # a lock file or a WAL that is there, as while serving
        return path
    if target == "other-store":
        shutil.copyfile(db, folder / "other.db")
        return folder / "other.db"
    if target == "fifo":
        os.mkfifo(folder / "a.fifo")
        return folder / "a.fifo"
    if target == "folder":
        (folder / "a.dir").mkdir()
        return folder / "a.dir"
    os.mknod(folder / "a.dev", 0o666 | stat.S_IFCHR, os.makedev(1, 7))
    return folder / "a.dev"


def _reach(folder: Path, real: Path, form: str) -> str:
    """A path naming `real` in this form, relative to `folder` (the command's working folder)."""
    if form == "absolute":
        return str(real)
    if form == "relative":
        return os.path.relpath(real, folder)
    if form == "dotdot":
        (folder / "sub").mkdir(exist_ok=True)
        return os.path.join("sub", "..", os.path.relpath(real, folder))
    if form == "symlink":
        (folder / "out.link").symlink_to(real)
        return "out.link"
    if form == "symlink-chain":
        (folder / "one.link").symlink_to(real)
        (folder / "two.link").symlink_to("one.link")
        return "two.link"
    if form == "symlinked-folder":
        (folder / "here").symlink_to(real.parent)
        return os.path.join("here", real.name)
    if real.is_file():
        os.link(real, folder / "out.hard")
        return "out.hard"
    return str(real)                    # a hard link to a folder or a special file: the file itself


def _fingerprint(folder: Path) -> dict[str, object]:
    found: dict[str, object] = {}
    for path in sorted(folder.iterdir()):
        mode = os.lstat(path).st_mode
        found[path.name] = (hashlib.sha256(path.read_bytes()).hexdigest() if stat.S_ISREG(mode) else
                            os.readlink(path) if stat.S_ISLNK(mode) else stat.S_IFMT(mode))
    return found


@fuzz(12)
@given(st.sampled_from(sorted(COMMANDS)), st.sampled_from(TARGETS), st.sampled_from(FORMS))
def test_a_hostile_output_path_never_touches_the_evidence(original, command, target, form):
    with tempfile.TemporaryDirectory(prefix="gaps-fuzz-out-") as tmp:
        folder = Path(tmp)
        db = folder / "gaps.db"
        shutil.copyfile(original, db)
        shutil.copyfile(f"{original}.cache", f"{db}.cache")
        aim = _target(folder, db, target)
        given_path = _reach(folder, aim, form)
        before = _fingerprint(folder)
        with contextlib.chdir(folder):
            result = gaps(*COMMANDS[command](given_path), db=db)
        assert result.exit_code == 2, (command, target, form, result.output[-400:])
        assert "refusing to write" in result.output and given_path in result.output, result.output[-400:]
        after = _fingerprint(folder)
        assert after == before, (command, target, form)
