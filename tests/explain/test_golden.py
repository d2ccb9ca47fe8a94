"""Golden files: the explanation of every verdict path, as an investigator reads it.

Each file in tests/explain/golden/ was read as a reader would (does the verdict sentence say what
happened, does every fact cite its event, do the counterfactuals separate what the vehicle did from
what it found?) before it was accepted. A change to the wording shows here as a diff; regenerate
with GAPS_UPDATE_GOLDEN=1 and read the diff before committing it.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from tests.helpers.explained_cases import CASES, explained
from explain.explanation_formats import render

GOLDEN = Path(__file__).with_name("golden")
UPDATE = os.environ.get("GAPS_UPDATE_GOLDEN") == "1"

# name -> the renderings kept as golden files (format, level)
EXTRA = {
    "paper_car_173_punishable": [("md", "standard"), ("json", None), ("text", "summary"), ("text", "full")],
    "paper_ambulance_253_mitigated": [("md", "standard")],
}


def check(name: str, text: str) -> None:
    path = GOLDEN / name
    if UPDATE or not path.exists():
        path.write_text(text, encoding="utf-8")
        if not UPDATE:
            pytest.fail(f"wrote the new golden file {path}; read it, then run again")
    assert text == path.read_text(encoding="utf-8"), f"{name} differs (GAPS_UPDATE_GOLDEN=1 rewrites it)"


@pytest.mark.parametrize("name", sorted(CASES))
def test_golden_text(tmp_path, name):
    _, doc = explained(tmp_path / "s.db", name)
    check(f"{name}.txt", render(doc, "text", "standard"))
    for fmt, level in EXTRA.get(name, []):
        if fmt == "json":
            check(f"{name}.json", json.dumps(doc, indent=2, ensure_ascii=False, sort_keys=True) + "\n")
        else:
            suffix = "md" if fmt == "md" else "txt"
            check(f"{name}.{level}.{suffix}" if level != "standard" or fmt != "md" else f"{name}.md",
                  render(doc, fmt, level))


def test_every_golden_file_belongs_to_a_case():
    """No stale golden file lingers after a case is renamed or removed."""
    for path in GOLDEN.iterdir():
        assert path.name.split(".")[0] in CASES, f"{path.name} belongs to no case"
