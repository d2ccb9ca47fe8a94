"""The rulebooks shipped with the project (`reasoner/rules/*.le`)."""
from __future__ import annotations

from pathlib import Path

RULES_DIR = Path(__file__).with_name("rules")
CURRENT = "paper.le"     # what a run that names no rulebook is judged with


def bundled(name: str = CURRENT) -> str:
    return (RULES_DIR / name).read_text(encoding="utf-8")
