"""A clone carries the design document and the legal texts its docs cite (issue 39: links to
`../shared/…` files a clone lacks). They are copies of the originals kept beside the repository.
The law is copied byte for byte. The design is the project's own and moves with the code: where
the original is there, the copy must be it plus exactly the changes recorded in
`docs/design-changes.diff`, so that no contract changes without the record showing it, and a new
original is noticed."""
from __future__ import annotations

import difflib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
COPIES = {"docs/legal/road-junctions-170-183.md": "highway-code/road-junctions-170-183.md"}
DESIGN, DESIGN_CHANGES = "docs/design.md", "docs/design-changes.diff"


def design_diff(original: str, copy: str) -> str:
    """The unified diff from the original DESIGN.md to the repository's, as recorded."""
    return "".join(difflib.unified_diff(original.splitlines(keepends=True), copy.splitlines(keepends=True),
                                        "shared/DESIGN.md", DESIGN, n=1))


@pytest.mark.parametrize("copy", sorted(COPIES))
def test_the_copy_in_the_clone_is_the_original(copy: str) -> None:
    original = SHARED / COPIES[copy]
    assert (ROOT / copy).exists(), f"{copy} is missing from the clone"
    if not original.exists():
        pytest.skip(f"no original at {original} (a clone alone): the copy is what there is")
    assert (ROOT / copy).read_bytes() == original.read_bytes(), \
        f"{copy} differs from {original}: copy the original over it in the same commit as the change"


def test_the_design_is_the_original_with_its_recorded_changes() -> None:
    original = SHARED / "DESIGN.md"
    assert (ROOT / DESIGN).exists() and (ROOT / DESIGN_CHANGES).exists()
    if not original.exists():
        pytest.skip(f"no original at {original} (a clone alone): the copy is what there is")
    found = design_diff(original.read_text(encoding="utf-8"), (ROOT / DESIGN).read_text(encoding="utf-8"))
    assert found == (ROOT / DESIGN_CHANGES).read_text(encoding="utf-8"), (
        f"{DESIGN} differs from {original} by other changes than {DESIGN_CHANGES} records: "
        "record a contract change there in the same commit, or take in a new original")


def test_no_doc_sends_a_reader_to_a_file_a_clone_lacks() -> None:
    docs = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    cited = [f"{p.relative_to(ROOT)}:{n}" for p in docs
             for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
             if "../shared/DESIGN.md" in line or "../shared/highway-code" in line]
    assert not cited, cited
