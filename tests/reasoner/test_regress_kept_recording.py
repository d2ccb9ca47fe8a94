"""A recording regressed again is judged from what was kept of it (store/kept_recording.py): no
import, the same result to the byte; and nothing kept can make a result different: another file,
an altered entry, another version of the code or a question it did not keep send the recording
through its import again."""
from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from reasoner.regress import recording as regress_recording
from reasoner.regress.cluster import regress_recordings
from store import Store
from store.cache import kept_recording
from store.transfer import export_run

from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401  (fixtures)


@pytest.fixture(autouse=True)
def cache_home(tmp_path, monkeypatch) -> Path:
    """Each test's kept recordings in a folder of its own."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache-home"))
    monkeypatch.delenv(kept_recording.BUDGET_ENV, raising=False)
    return tmp_path / "cache-home"


@pytest.fixture
def recording(db, tmp_path) -> Path:  # noqa: F811
    path = tmp_path / "run.jsonl"
    with Store.open_read_only(db) as store:
        export_run(store, R.RUN, path)
    return path


@pytest.fixture
def imports(monkeypatch) -> list:
    """Each import of a recording into a temporary store, counted."""
    calls: list = []
    real = regress_recording.import_file
    monkeypatch.setattr(regress_recording, "import_file", lambda store, path: calls.append(path) or real(store, path))
    return calls


def regressed(recording: Path, rules: Path) -> str:
    return json.dumps(regress_recordings([recording], [str(rules)]).to_json(), sort_keys=True)


def kept_files(cache_home: Path) -> list[Path]:
    return sorted((cache_home / "mind-the-gaps" / "recordings").glob("*.cache"))


def test_a_recording_regressed_again_is_not_imported_and_gives_the_same(recording, new_rules, imports,  # noqa: F811
                                                                         cache_home, monkeypatch):
    first = regressed(recording, new_rules)
    assert len(imports) == 1 and json.loads(first)["changed"]
    (kept,) = kept_files(cache_home)
    assert kept.name == kept_recording.recording_digest(recording) + ".cache"
    assert regressed(recording, new_rules) == first
    other = R.edited(new_rules.parent.parent / "other", "penalties.le",
                     old="traffic light offence carries a fixed penalty of 100 pounds",
                     new="traffic light offence carries a fixed penalty of 200 pounds")
    kept = regressed(recording, other)
    assert len(imports) == 1, "the kept recording answers for another rulebook"
    assert "200" in kept
    monkeypatch.setenv(kept_recording.BUDGET_ENV, "0")           # nothing kept: imported and judged afresh
    assert regressed(recording, other) == kept and kept != first
    assert len(imports) == 2


def test_a_file_of_other_bytes_is_imported(recording, new_rules, imports, tmp_path):  # noqa: F811
    regressed(recording, new_rules)
    other = tmp_path / "other.jsonl"
    other.write_text(recording.read_text() + '{"v": 1, "run": "run", "src": "vehicle/5", "kind": "vehicle.decision"}\n')
    (result,) = regress_recordings([other], [str(new_rules)]).runs
    assert len(imports) == 2
    assert result.problems == (f"{other}: 1 event(s) refused on import, not judged (`gaps import` says why)",)
    (again,) = regress_recordings([other], [str(new_rules)]).runs
    assert len(imports) == 2 and again.problems == result.problems, "the import's problems are kept too"


def test_an_altered_entry_is_not_believed(recording, new_rules, imports, cache_home):  # noqa: F811
    """An entry altered so that it would still answer every question (the count of refused
    events raised: a problem said of a file that had none) is dropped by its seal."""
    first = regressed(recording, new_rules)
    (kept,) = kept_files(cache_home)
    with sqlite3.connect(kept) as conn:
        payload, = conn.execute("SELECT payload FROM derived WHERE kind = 'recording'").fetchone()
        conn.execute("UPDATE derived SET payload = ? WHERE kind = 'recording'",
                     (json.dumps({**json.loads(payload), "rejected": 5}),))
    assert regressed(recording, new_rules) == first
    assert len(imports) == 2


def test_what_another_version_of_the_code_kept_is_not_used(recording, new_rules, imports, monkeypatch):  # noqa: F811
    first = regressed(recording, new_rules)
    monkeypatch.setattr(regress_recording, "code_version", lambda: "another version")
    assert regressed(recording, new_rules) == first
    assert len(imports) == 2


def test_a_question_the_kept_part_cannot_answer_sends_the_file_through_its_import(
        recording, new_rules, imports, monkeypatch):  # noqa: F811
    first = regressed(recording, new_rules)
    monkeypatch.setattr(kept_recording, "KEPT_KINDS", ("run.start",))   # as if the incidents' kind were not kept
    assert regressed(recording, new_rules) == first
    assert len(imports) == 2


def test_a_rule_that_finds_new_incidents_has_them_measured_from_the_import(recording, new_rules, imports,  # noqa: F811
                                                                           monkeypatch):
    """Entering on green made a potential violation: a crossing no case measured before, whose
    measurement needs the run's events (the signals, the states), so the file is imported."""
    regressed(recording, new_rules)
    green = R.edited(new_rules.parent.parent / "green", "monitors.le", cut=(R.RED_CROSSED, R.RED_SNAPSHOT),
                     add=R.GREEN_RULE)
    kept = regressed(recording, green)
    assert len(imports) == 2
    monkeypatch.setenv(kept_recording.BUDGET_ENV, "0")
    assert regressed(recording, green) == kept


def test_a_kept_recording_asked_what_it_did_not_keep_says_so(recording, new_rules):  # noqa: F811
    regressed(recording, new_rules)
    kept = kept_recording.open_kept(kept_recording.recording_digest(recording), regress_recording.code_version())
    assert kept is not None
    with kept:
        assert [e["kind"] for e in kept.events(R.RUN, kinds=["run.start"])] == ["run.start"]
        with pytest.raises(kept_recording.NotKept):
            kept.events(R.RUN, kinds=["entity.state"])
        assert kept.missed and "entity.state" in kept.missed
        with pytest.raises(kept_recording.NotKept):
            kept.sources(R.RUN)


def test_nothing_is_kept_under_a_budget_of_nothing(recording, new_rules, imports, cache_home,  # noqa: F811
                                                   monkeypatch):
    monkeypatch.setenv(kept_recording.BUDGET_ENV, "0")
    first = regressed(recording, new_rules)
    assert regressed(recording, new_rules) == first
    assert len(imports) == 2 and kept_files(cache_home) == []


def test_the_folder_is_trimmed_to_its_budget_oldest_first(cache_home, monkeypatch):
    import os
    folder = cache_home / "mind-the-gaps" / "recordings"
    folder.mkdir(parents=True)
    for n, name in enumerate(("old", "mid", "new")):
        path = folder / f"{name}.cache"
        path.write_bytes(b"x" * (600 << 10))
        os.utime(path, (1000 + n, 1000 + n))
    monkeypatch.setenv(kept_recording.BUDGET_ENV, "1")          # 1 MB: room for one
    gone = kept_recording.trim(keep_path=str(folder / "mid.cache"))
    assert sorted(Path(p).name for p in gone) == ["new.cache", "old.cache"]
    assert [p.name for p in kept_files(cache_home)] == ["mid.cache"]
