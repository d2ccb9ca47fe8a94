"""A clone carries the design document and the legal texts its docs cite (issue 39: links to
`../shared/…` files a clone lacks). They are copies of the originals kept beside the repository;
where those are there, the copies must be the same, byte for byte, so that a change to the
contract lands in both."""
from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
COPIES = {"docs/design.md": "DESIGN.md",
          "docs/legal/road-junctions-170-183.md": "highway-code/road-junctions-170-183.md"}


@pytest.mark.parametrize("copy", sorted(COPIES))
def test_the_copy_in_the_clone_is_the_original(copy: str) -> None:
    original = SHARED / COPIES[copy]
    assert (ROOT / copy).exists(), f"{copy} is missing from the clone"
    if not original.exists():
        pytest.skip(f"no original at {original} (a clone alone): the copy is what there is")
    assert (ROOT / copy).read_bytes() == original.read_bytes(), \
        f"{copy} differs from {original}: copy the original over it in the same commit as the change"


def test_no_doc_sends_a_reader_to_a_file_a_clone_lacks() -> None:
    docs = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    cited = [f"{p.relative_to(ROOT)}:{n}" for p in docs
             for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
             if "../shared/DESIGN.md" in line or "../shared/highway-code" in line]
    assert not cited, cited
