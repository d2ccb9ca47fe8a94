"""Command-line arguments fuzzed: any mix of the read commands, their options and hostile values
(unknown runs, bad times, odd text, missing files) against a small store ends with an exit code
that means something (0, 1 or 2), never a traceback, and never changes the store's bytes."""
from __future__ import annotations

import contextlib
import hashlib

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim_replay.paper import RUN, paper_run
from store import Store
from tests.fuzz.budget import fuzz
from tests.helpers.cli import gaps

COMMANDS = [["runs"], ["verify"], ["incidents"], ["scene"], ["explain"], ["quarantine"], ["export"],
            ["rules", "check"], ["rules", "query"]]
OPTIONS = ["--run", "--at", "--json", "--vehicle", "--kind", "--format", "-o", "--order", "--rules", "--query",
           "--since", "--limit", "--explain", "--help"]
VALUES = [RUN, "nope", "10s", "-5s", "1e99", "2024-11-21T08:00:10Z", "173", "253", "0", "-1", "99999999999999999999",
          "mcap", "jsonl", "time", "chain", "\x1b[31m", "é", "", "*", "../../etc/passwd", "/nonexistent/x.le"]


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    path = tmp_path_factory.mktemp("fuzz-cli") / "gaps.db"
    with Store(path) as store:
        store.append(paper_run())
    return path


@fuzz(15)
@given(st.sampled_from(COMMANDS), st.lists(st.one_of(st.sampled_from(OPTIONS), st.sampled_from(VALUES)), max_size=6))
def test_read_commands_with_any_arguments(db, tmp_path_factory, command, args):
    before = hashlib.sha256(db.read_bytes()).hexdigest()
    with contextlib.chdir(tmp_path_factory.mktemp("cwd")):  # an export's file lands here, not in the checkout
        result = gaps(*command, *args, db=db)  # tests.helpers.cli.gaps fails on any traceback or stray exception
    assert result.exit_code in (0, 1, 2), (command, args, result.output[-500:])
    assert hashlib.sha256(db.read_bytes()).hexdigest() == before
