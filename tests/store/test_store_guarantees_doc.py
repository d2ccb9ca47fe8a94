"""docs/guarantees.md names a test for every promise: each named file and test must exist, so a
promise cannot outlive the test that backed it."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).parents[2]
DOC = ROOT / "docs" / "guarantees.md"


def named_tests() -> list[tuple[str, str | None]]:
    """(file, test or None) for every `tests/...py[::name][, ::name]` the promises table cites."""
    found = []
    for line in DOC.read_text(encoding="utf-8").splitlines():
        if not line.startswith("|") or "tests/" not in line:
            continue
        cell = line.rstrip(" |").rsplit("|", 1)[-1]
        current = None
        for token in re.findall(r"tests/[\w/]+\.py(?:::\w+)?|::\w+", cell):
            path, _, name = token.partition("::")
            current = path or current
            found.append((current, name or None))
    return found


def test_every_test_the_guarantees_name_exists():
    cited = named_tests()
    assert len(cited) >= 15
    for path, name in cited:
        source = ROOT / path
        assert source.is_file(), path
        if name is not None:
            assert re.search(rf"^def {name}\(", source.read_text(encoding="utf-8"), flags=re.M), f"{path}::{name}"
