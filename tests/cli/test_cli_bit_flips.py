"""Random bit flips in a store file (issue 15, finding 6: 60 flips gave 5 tracebacks, and 3 changed
what was read while verify passed). Each of 60 seeded flips, of one bit of a byte that holds data
(a zero byte is most often free space), is made in a copy of a small store; `gaps verify`, `runs`,
`incidents` and `export` then run through the command line in a child process. Every case must end
in a clean error (an exit code of 1 or 2 and a message, no traceback) or in a store that verifies
and whose every read equals the original's."""

from __future__ import annotations

import json
import random
import subprocess
import sys
from pathlib import Path

import pytest

from sim_replay.paper import RUN, paper_run
from store import Store

ROOT = Path(__file__).resolve().parents[2]
SEEDS = range(60)


def commands(db: Path, out: Path) -> list[list[str]]:
    return [["verify", "--json", "--db", str(db)], ["runs", "--json", "--db", str(db)],
            ["incidents", "--json", "--db", str(db)], ["export", "--run", RUN, "-o", str(out), "--db", str(db)]]


def flipped(original: bytes, seed: int) -> bytes:
    rng = random.Random(seed)
    data = bytearray(original)
    position = rng.choice([i for i, byte in enumerate(original) if byte])
    data[position] ^= 1 << rng.randrange(8)
    return bytes(data)


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory) -> tuple[list[dict], list[list[dict]], Path]:
    folder = tmp_path_factory.mktemp("flips")
    original = folder / "original.db"
    with Store(original) as store:
        store.append(paper_run())
    data = original.read_bytes()
    cases = [commands(original, folder / "original.jsonl")]
    for seed in SEEDS:
        copy = folder / f"flip-{seed}.db"
        copy.write_bytes(flipped(data, seed))
        cases.append(commands(copy, folder / f"flip-{seed}.jsonl"))
    child = subprocess.run([sys.executable, "-m", "tests.helpers.cli_child"], input=json.dumps(cases), cwd=ROOT,
                           capture_output=True, text=True, timeout=600, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert child.returncode == 0, child.stderr[-3000:]
    results = json.loads(child.stdout)
    return results[0], results[1:], folder


def test_the_original_reads_cleanly(outcomes):
    original, _, folder = outcomes
    assert [r["code"] for r in original] == [0, 0, 0, 0]
    assert json.loads(original[2]["out"]) and (folder / "original.jsonl").stat().st_size > 0


def test_no_flip_gives_a_traceback_and_every_error_says_something(outcomes):
    _, flips, _ = outcomes
    for seed, results in zip(SEEDS, flips):
        for command, result in zip(["verify", "runs", "incidents", "export"], results):
            assert result["code"] in (0, 1, 2), (seed, command, result["err"][-1500:])
            assert "Traceback" not in result["err"] + result["out"], (seed, command)
            if result["code"] != 0:
                said = result["err"] if command != "verify" else result["out"] + result["err"]
                assert said.strip(), (seed, command)


def test_a_flip_verify_passes_changes_nothing_that_is_read(outcomes):
    original, flips, folder = outcomes
    passed = 0
    for seed, results in zip(SEEDS, flips):
        if results[0]["code"] != 0:
            continue
        passed += 1
        assert [r["code"] for r in results] == [0, 0, 0, 0], seed
        assert [r["out"] for r in results[1:3]] == [r["out"] for r in original[1:3]], seed
        assert (folder / f"flip-{seed}.jsonl").read_bytes() == (folder / "original.jsonl").read_bytes(), seed
    failed = len(SEEDS) - passed
    assert passed and failed  # both kinds of case were tried
