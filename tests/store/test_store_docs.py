"""docs/store.md shows how to check a run without this software; that recipe must keep working."""

import re
from pathlib import Path

from tests.helpers.store_testkit import event

from store import canonical_json

DOC = Path(__file__).parents[2] / "docs" / "store.md"


def recipe() -> str:
    """The chain check (the doc's other Python block checks a signature)."""
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    [code] = [block for block in blocks if "sqlite3.connect" in block]
    return code


def test_the_independent_check_agrees_with_the_store(store, db_path, monkeypatch, capsys):
    store.append([event(i, run="paper-junctions", body={"facts": [f"173 fährt {i}"]}) for i in range(5)])
    [checkpoint] = store.checkpoints("paper-junctions")
    monkeypatch.chdir(db_path.parent)
    exec(recipe(), {})
    assert capsys.readouterr().out.strip() == f"head {checkpoint['head']} over 5 events"


def test_the_example_event_in_the_doc_is_its_canonical_form():
    ev = {"v": 1, "run": "demo-001", "src": "vehicle/173", "seq": 0, "t": 1732184100350000000,
          "kind": "vehicle.perception", "body": {"facts": ["173 is of type car", "173 has red light"]}}
    assert canonical_json(ev).decode() in DOC.read_text(encoding="utf-8")
