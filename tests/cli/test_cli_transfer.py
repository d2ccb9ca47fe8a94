"""`gaps import` and `gaps export` as a user runs them: counts, --json, exit codes, clear
messages without tracebacks, for JSONL and MCAP."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event, heads, out_of_order_store


@pytest.fixture
def db(tmp_path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i, run="r1") for i in range(5)])
    return path


def test_export_then_import_both_formats(db, tmp_path):
    for name in ("r1.mcap", "r1.jsonl"):
        out = gaps("export", "--run", "r1", "-o", tmp_path / name, "--db", db)
        assert out.exit_code == 0, out.stderr
        assert f"exported run r1: 5 events" in out.stdout
        fresh = tmp_path / f"{name}.db"
        imported = gaps("import", tmp_path / name, "--db", fresh, "--json")
        assert imported.exit_code == 0, imported.stderr
        report = json.loads(imported.stdout)
        assert (report["stored"], report["duplicates"], report["rejected"]) == (5, 0, 0)
        assert report["truncated"] is None and report["details"] == []
        assert gaps("verify", "--db", fresh).exit_code == 0
    mcap_report = json.loads(gaps("import", tmp_path / "r1.mcap", "--db", db, "--json").stdout)
    assert (mcap_report["stored"], mcap_report["duplicates"]) == (0, 5)
    assert mcap_report["chains"][0]["match"] is True


def test_export_no_scene(db, tmp_path):
    result = gaps("export", "--run", "r1", "-o", tmp_path / "plain.mcap", "--no-scene", "--db", db, "--json")
    assert result.exit_code == 0 and json.loads(result.stdout)["derived"] == 0


def test_import_text_output_names_rejections_and_exits_0(db, tmp_path):
    path = tmp_path / "mixed.jsonl"
    path.write_bytes(json.dumps(event(0, run="r2")).encode() + b"\n{oops\n\n")
    result = gaps("import", path, "--db", db)
    assert result.exit_code == 0
    assert "stored 1, duplicates 0, rejected 1, skipped 1" in result.stdout
    assert f"{path}:2: event: malformed JSON" in result.stdout
    assert "`gaps quarantine` lists them" in result.stdout


def test_import_json_lists_the_first_100_rejections(tmp_path):
    path = tmp_path / "bad.jsonl"
    path.write_bytes(b"nope\n" * 150)
    result = gaps("import", path, "--db", tmp_path / "new.db", "--json", "--fast")
    report = json.loads(result.stdout)
    assert result.exit_code == 0 and report["rejected"] == 150 and len(report["details"]) == 100
    assert report["details"][99] == {"origin": f"{path}:100", "reason": report["details"][99]["reason"]}
    assert set(report) >= {"stored", "duplicates", "rejected", "skipped", "details", "truncated"}


def test_import_creates_the_store(tmp_path, db):
    gaps("export", "--run", "r1", "-o", tmp_path / "r1.jsonl", "--db", db)
    target = tmp_path / "created.db"
    assert gaps("import", tmp_path / "r1.jsonl", "--db", target).exit_code == 0
    assert target.is_file()


def test_truncated_mcap_is_reported(db, tmp_path):
    gaps("export", "--run", "r1", "-o", tmp_path / "r1.mcap", "--db", db)
    data = (tmp_path / "r1.mcap").read_bytes()
    (tmp_path / "cut.mcap").write_bytes(data[: len(data) // 3])
    text = gaps("import", tmp_path / "cut.mcap", "--db", tmp_path / "cut.db")
    assert text.exit_code == 0 and "TRUNCATED at byte" in text.stdout
    report = json.loads(gaps("import", tmp_path / "cut.mcap", "--db", tmp_path / "cut.db", "--json").stdout)
    assert report["truncated"]["file_size"] == len(data) // 3


@pytest.mark.parametrize("args, message", [
    (["import", "absent.jsonl"], "no such file: absent.jsonl"),
    (["import", "events.txt"], "cannot tell the format from the extension '.txt'"),
    (["import", "events.txt", "--format", "xml"], "unknown format 'xml'"),
    (["import", "fake.mcap"], "fake.mcap: not an MCAP file"),
    (["export", "--run", "nope", "-o", "x.mcap"], "no run 'nope'"),
    (["export", "--run", "r1", "-o", "x.csv"], "cannot tell the format"),
    (["export", "--run", "r1", "-o", "x.jsonl", "--order", "random"], "unknown order 'random'"),
    (["export", "--run", "r1", "-o", "no/such/folder/x.jsonl"], "cannot write"),
])
def test_user_mistakes_exit_2_with_a_message(db, tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "events.txt").write_text("{}")
    (tmp_path / "fake.mcap").write_text("not really")
    result = gaps(*args, "--db", db)
    assert result.exit_code == 2
    assert message in result.stderr
    assert not (tmp_path / "x.mcap").exists() and not (tmp_path / "x.jsonl").exists()


def test_a_missing_file_does_not_create_a_store(tmp_path):
    result = gaps("import", tmp_path / "absent.mcap", "--db", tmp_path / "never.db")
    assert result.exit_code == 2 and not (tmp_path / "never.db").exists()


def test_export_needs_an_existing_store(tmp_path):
    result = gaps("export", "--run", "r1", "-o", tmp_path / "x.mcap", "--db", tmp_path / "none.db")
    assert result.exit_code == 2 and "no event store" in result.stderr


@pytest.mark.parametrize("suffix", ["jsonl", "mcap"])
def test_gaps_export_then_import_gives_the_same_chain_heads(tmp_path, suffix):
    """An export is in chain order by default, so anyone can re-import it and recompute the heads."""
    out_of_order = out_of_order_store(tmp_path / "a.db")
    for run in ("r1", "r2"):
        exported = gaps("export", "--run", run, "-o", tmp_path / f"{run}.{suffix}", db=out_of_order)
        assert exported.exit_code == 0 and "in chain order" in exported.output, exported.output
        imported = gaps("import", tmp_path / f"{run}.{suffix}", db=tmp_path / "b.db")
        assert imported.exit_code == 0, imported.output
    with Store.open_read_only(out_of_order) as a, Store.open_read_only(tmp_path / "b.db") as b:
        assert heads(a) == heads(b)
