"""One way to write a count and a duration across commands (issue 39: "48363 events" beside
"48,383 unsigned"; "5 s" and "0:01:00" in one table)."""
from __future__ import annotations

import json

import pytest

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event


@pytest.fixture(scope="module")
def thousand_db(tmp_path_factory):
    path = tmp_path_factory.mktemp("words") / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in range(1_234)])
    return path


def test_verify_and_runs_write_a_count_as_the_signature_tally_does(thousand_db):
    said = gaps("verify", db=thousand_db).stdout
    assert "r1: 1,234 events, chain ok" in said, said
    assert "signatures: 0 signed, 1,234 unsigned" in said, said
    assert "│ 1,234 " in gaps("runs", db=thousand_db).stdout


def test_runs_write_the_duration_as_the_options_take_it(thousand_db):
    shown = gaps("runs", db=thousand_db).stdout
    span = json.loads(gaps("runs", "--json", db=thousand_db).stdout)[0]["duration_ns"]
    from reasoner.when import format_duration, parse_duration
    assert format_duration(span) in shown and parse_duration(format_duration(span)) == span
    assert " s " not in shown and "0:0" not in shown


def test_a_scene_without_a_recorded_road_does_not_say_road_none(tmp_path):
    """`gaps scene` printed "road None" for a vehicle whose entity.state names no road (a foreign
    producer's, which may leave it out: DESIGN's kinds make it optional)."""
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(0, kind="entity.spawn", body={"type": "car"}),
                      event(1, kind="entity.state", body={"x": 1.0, "y": 2.0, "speed_mps": 3.0})])
    shown = gaps("scene", "--run", "r1", "--at", "0.1s", "--vehicle", "173", db=path)
    assert shown.exit_code == 0, shown.output
    assert "road None" not in shown.stdout, shown.stdout
