"""The reports that leave the store for `gaps import`, `gaps export` and `gaps verify --key` are
typed all the way down: each part a frozen value whose `to_json()` is the JSON the command prints,
with its keys in the order the command has always printed them (the --json outputs are compared
byte for byte before and after in the issue 38 work; tests/cli covers the commands)."""
from __future__ import annotations

import dataclasses
import json

import pytest
from tests.helpers.store_testkit import event

from store import Store
from store.keys import CheckpointKey, KeyCheck, KeyedRun, KeyProblem
from store.transfer import (ChainResult, Damage, ExportReport, ImportReport, Mismatch, Rejection, Skip, Truncation,
                            export_run, import_file)


def _frozen(value: object) -> None:
    field = dataclasses.fields(value)[0].name  # type: ignore[arg-type]
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(value, field, None)


@pytest.fixture
def source(tmp_path):
    with Store(tmp_path / "source.db") as store:
        for lo in range(0, 400, 100):     # several appends: several checkpoints
            store.append([event(i) for i in range(lo, lo + 100)])
        yield store


def test_a_jsonl_import_reports_its_rejections_and_skips_as_values(source, tmp_path):
    path = tmp_path / "mixed.jsonl"
    export_run(source, "r1", tmp_path / "r1.jsonl")
    good = (tmp_path / "r1.jsonl").read_bytes().splitlines()[:3]
    path.write_bytes(b"\n".join([good[0], b"", b"not json", good[1], b"  ", good[2], b"{}"]) + b"\n")
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, path)
    assert isinstance(report, ImportReport)
    assert [type(d) for d in report.details] == [Rejection, Rejection]
    assert report.details[0].origin == f"{path}:3"
    assert report.skips == {"blank lines": Skip("blank lines", 2, "a blank line holds no event")}
    for part in (*report.details, *report.skips.values()):
        _frozen(part)
    out = report.to_json()
    assert list(out) == ["file", "format", "stored", "duplicates", "rejected", "quarantine_full", "skipped",
                         "details", "skips", "truncated", "damaged", "chains"]
    assert [list(d) for d in out["details"]] == [["origin", "reason"]] * 2
    assert out["skips"] == [{"what": "blank lines", "count": 2, "reason": "a blank line holds no event"}]
    assert (out["truncated"], out["damaged"], out["chains"]) == (None, [], [])


def test_a_cut_mcap_reports_its_cut_and_chain_as_values(source, tmp_path):
    full = tmp_path / "r1.mcap"
    exported = export_run(source, "r1", full, scene=False)
    assert isinstance(exported, ExportReport) and exported.order == "chain"
    assert list(exported.to_json()) == ["file", "format", "run", "order", "events", "derived", "bytes", "chain_order"]
    data = full.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[:len(data) - 50])
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, cut)
    truncation = report.truncated
    assert isinstance(truncation, Truncation) and truncation.stored == report.stored == 400
    assert truncation.cut.file_size == len(data) - 50
    (chain,) = report.chains
    assert isinstance(chain, ChainResult) and chain.match is True and chain.first_mismatch is None
    for part in (truncation, truncation.cut, chain):
        _frozen(part)
    out = json.loads(json.dumps(report.to_json()))
    assert list(out["truncated"]) == ["offset", "file_size", "reason", "record", "declared", "data_complete",
                                      "unreadable_bytes", "messages_read", "stored"]
    assert out["truncated"]["unreadable_bytes"] == truncation.cut.unreadable_bytes == len(data) - 50 - \
        truncation.cut.offset
    assert list(out["chains"][0]) == ["run", "order", "exported_events", "exported_head", "file_events", "file_head",
                                      "checkpoints", "checkpoints_matched", "first_mismatch", "store_head",
                                      "malformed_metadata", "match"]  # chain_order only when not followed


def test_the_parts_say_the_json_they_stand_for():
    damage = Damage(8, "Chunk", "cannot be decoded")
    assert damage.to_json() == {"offset": 8, "record": "Chunk", "reason": "cannot be decoded"}
    mismatch = Mismatch(24, "ab" * 32, "cd" * 32)
    assert list(mismatch.to_json()) == ["count", "exported_head", "file_head"]
    chain = ChainResult("r", "chain", 30, "ab" * 32, 30, "cd" * 32, 3, 2, mismatch, "cd" * 32, 0, False,
                        chain_order="not followed to the end")
    assert chain.to_json()["first_mismatch"] == mismatch.to_json()
    assert list(chain.to_json())[-2:] == ["match", "chain_order"]
    for part in (damage, mismatch, chain):
        _frozen(part)


def test_the_key_check_says_its_problem_and_runs_as_values(tmp_path):
    key = CheckpointKey.create(tmp_path / "checkpoint.key")
    db = tmp_path / "s.db"
    with Store(db) as store:
        store.append([event(i) for i in range(3)])
    with Store.open_read_only(db) as store:
        _, keyed = store.check_anchors((), key.public)
    assert isinstance(keyed, KeyCheck) and not keyed.ok
    assert isinstance(keyed.problem, KeyProblem) and keyed.problem.run == "r1"
    assert "no checkpoint is signed by key" in keyed.problem.what
    (run,) = keyed.runs
    assert isinstance(run, KeyedRun) and (run.run, run.events, run.ok, run.what) == ("r1", 3, False,
                                                                                     keyed.problem.what)
    for part in (keyed.problem, run):
        _frozen(part)
    out = keyed.to_json()
    assert list(out) == ["key", "signed", "unsigned_before", "ok", "problem", "runs", "absent"]
    assert list(out["problem"]) == ["run", "count", "what"]
    assert list(out["runs"][0]) == ["run", "events", "signed_through", "since", "recorded", "signed",
                                    "unsigned_before", "ok", "what"]
