"""`gaps incidents`: one line per incident, filtered by verdict, vehicle or rule; --explain for
the full explanations; --json as before, filtered alike."""
import json

import pytest

from sim_replay.paper import RUN
from tests.helpers.cli import gaps


def test_one_line_per_incident(paper_db):
    result = gaps("incidents", "--run", RUN, db=paper_db)
    assert result.exit_code == 0, result.output
    first, second = result.stdout.splitlines()
    assert first.split() == ["1", "2024-11-21T08:00:10.000Z", "monitor/m1:1", "vehicle", "173", "enter", "the",
                             "junction", "HC", "176", "punishable", "£100", "+", "3", "points", "liable:",
                             "driver", "crossed", "2.444", "s", "after", "red", "(±", "0.567", "s)", "1", "finding:",
                             "decision", "fault"]
    assert second.startswith("  2  2024-11-21T08:00:40.000Z  monitor/m1:3  vehicle 253")
    assert "mitigated  no penalty  liable: none  crossed 2.444 s after red (± 0.567 s)  no findings" in second


@pytest.mark.parametrize("filters, ids", [
    (["--verdict", "mitigated"], ["monitor/m1:3"]),
    (["--vehicle", "173"], ["monitor/m1:1"]),
    (["--rule", "HC 176"], ["monitor/m1:1", "monitor/m1:3"]),
    (["--rule", "HC 999"], []),
    (["--verdict", "punishable", "--vehicle", "253"], []),
])
def test_filters_apply_to_lines_and_json(paper_db, filters, ids):
    lines = gaps("incidents", *filters, db=paper_db).stdout.splitlines()
    as_json = json.loads(gaps("incidents", *filters, "--json", db=paper_db).stdout)
    assert [d["id"] for d in as_json] == ids
    if ids:
        assert [line.split()[2] for line in lines] == ids
    else:
        assert lines == ["No potential violations recorded matching " + ", ".join(
            f"{flag[2:]} {value}" for flag, value in zip(filters[::2], filters[1::2])) + "."]


def test_an_unknown_verdict_is_a_usage_error(paper_db):
    result = gaps("incidents", "--verdict", "guilty", db=paper_db)
    assert result.exit_code == 2 and "unknown verdict 'guilty'; verdicts: punishable" in result.stderr


def test_explain_prints_the_full_explanations(paper_db):
    """Filtered or not, an incident keeps its number in the run: the one `gaps explain` takes."""
    out = gaps("incidents", "--explain", "--vehicle", "253", db=paper_db).stdout
    assert out.startswith(f"── incident 2: {RUN} monitor/m1:3 ──\nVehicle 253 committed a mitigated violation")
    assert "\nIn short\n--------\n" in out


def test_json_keeps_its_shape(paper_db):
    (first, _) = json.loads(gaps("incidents", "--json", db=paper_db).stdout)
    assert list(first)[:12] == ["id", "run", "t", "vehicle", "action", "monitor", "recorded", "rederived",
                                "rule", "law", "verdict", "why"]
    assert "proofs" not in first and "scenarios" not in first
