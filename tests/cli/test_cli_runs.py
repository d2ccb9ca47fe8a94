"""`gaps runs`: a table for people, --json for programs, the seqs missing, the chain status."""
import json

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import T0, event, tamper


def test_runs_json(db):
    result = gaps("runs", "--json", db=db)
    assert result.exit_code == 0
    r1, r2 = json.loads(result.stdout)
    assert r1 == {"run": "r1", "events": 8, "sources": ["sim/world", "vehicle/173"],
                  "first_t": T0, "last_t": T0 + 3_723_500_000_000, "start": "2024-11-21T10:15:00Z",
                  "end": "2024-11-21T11:17:03.5Z", "duration_ns": 3_723_500_000_000, "chain": "verified"}
    assert (r2["run"], r2["events"], r2["chain"]) == ("r2", 1, "verified")


def test_runs_table(db):
    result = gaps("runs", db=db)
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    header = next(line for line in lines if "run" in line and "chain" in line)
    for column in ("events", "sources", "start (UTC)", "end (UTC)", "duration"):
        assert column in header
    r1 = next(line for line in lines if "│ r1 " in line)
    for cell in ("8", "2024-11-21T10:15:00Z", "2024-11-21T11:17:03.5Z", "1h2m3.5s", "verified"):
        assert cell in r1


def test_runs_with_gaps(db):
    result = gaps("runs", "--gaps", "--json", db=db)
    listed = json.loads(result.stdout)
    assert [r["run"] for r in listed["runs"]] == ["r1", "r2"]
    assert listed["gaps"] == [{"run": "r1", "src": "vehicle/173", "missing": [[3, 4], [7, 8]], "highest": 9}]
    text = gaps("runs", "--gaps", db=db).stdout
    assert "3-4, 7-8" in text and "missing seqs" in text


def test_runs_without_gaps_says_so(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(0)])
    assert "No gaps" in gaps("runs", "--gaps", db=path).stdout


def test_runs_shows_a_broken_chain(db):
    tamper(db, ("UPDATE events SET t = t + 1 WHERE run = 'r2'", ()))
    result = gaps("runs", "--json", db=db)
    assert result.exit_code == 0  # a listing, not a check: `gaps verify` is the one that fails
    assert {r["run"]: r["chain"] for r in json.loads(result.stdout)} == {"r1": "verified", "r2": "broken"}


def test_runs_without_verifying(db):
    result = gaps("runs", "--no-verify", "--json", db=db)
    assert {r["chain"] for r in json.loads(result.stdout)} == {"not checked"}


def test_an_empty_store(tmp_path):
    path = tmp_path / "gaps.db"
    Store(path).close()
    assert gaps("runs", db=path).stdout.strip() == "The store holds no runs."
    assert gaps("runs", "--json", db=path).stdout.strip() == "[]"
    assert gaps("quarantine", db=path).stdout.strip() == "Nothing was refused."


RUNS_JSON = """[
  {
    "run": "r1",
    "events": 8,
    "sources": [
      "sim/world",
      "vehicle/173"
    ],
    "first_t": 1732184100000000000,
    "last_t": 1732187823500000000,
    "start": "2024-11-21T10:15:00Z",
    "end": "2024-11-21T11:17:03.5Z",
    "duration_ns": 3723500000000,
    "chain": "verified"
  },
  {
    "run": "r2",
    "events": 1,
    "sources": [
      "monitor/m1"
    ],
    "first_t": 1732184100000000000,
    "last_t": 1732184100000000000,
    "start": "2024-11-21T10:15:00Z",
    "end": "2024-11-21T10:15:00Z",
    "duration_ns": 0,
    "chain": "verified"
  }
]
"""


def test_runs_json_is_byte_for_byte_what_programs_read(db):
    """Key order and layout too: scripts that diff or grep the output depend on them."""
    assert gaps("runs", "--json", db=db).stdout == RUNS_JSON
    with_gaps = gaps("runs", "--gaps", "--json", db=db).stdout
    runs_part = "\n".join("  " + line for line in RUNS_JSON.rstrip("\n").splitlines())
    assert with_gaps.startswith('{\n  "runs": ' + runs_part.lstrip() + ',\n  "gaps": [\n')


def test_runs_live_lists_each_sources_liveliness_and_losses_on_the_wire(tmp_path):
    from store.wire import LivelinessChange, WireMiss
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(0, src="vehicle/173"), event(0, src="vehicle/9")])
        store.record_wire([LivelinessChange("r1", "vehicle/173", True, T0, None),
                           LivelinessChange("r1", "vehicle/9", True, T0, None),
                           LivelinessChange("r1", "vehicle/173", False, T0 + 7_000_000_000, 0)],
                          [WireMiss("r1", "vehicle/9", "entity.state", 4, T0 + 8_000_000_000, 0)])
    listed = json.loads(gaps("runs", "--live", "--gaps", "--json", db=path).stdout)
    assert listed["liveliness"] == [
        {"run": "r1", "src": "vehicle/173", "alive": False, "appeared_at": T0, "disappeared_at": T0 + 7_000_000_000,
         "last_seq": 0, "changes": 2},
        {"run": "r1", "src": "vehicle/9", "alive": True, "appeared_at": T0, "disappeared_at": None,
         "last_seq": None, "changes": 1}]
    assert listed["wire_misses"] == [{"run": "r1", "src": "vehicle/9", "kind": "entity.state", "count": 4,
                                      "at": T0 + 8_000_000_000, "after_seq": 0}]
    text = gaps("runs", "--live", db=path).stdout
    assert "2024-11-21T10:15:07Z" in text and "alive" in text and "token appeared" in text
