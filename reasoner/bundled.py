"""The rulebooks shipped with the project (`reasoner/rules/*.le`)."""
from __future__ import annotations

from pathlib import Path

RULES_DIR = Path(__file__).with_name("rules")
PAPER = "paper.le"       # the paper's own listings: what the demo's vehicles and monitor decide with


def bundled(name: str = PAPER) -> str:
    return (RULES_DIR / name).read_text(encoding="utf-8")

# What a run that records no rulebook (or not one for a stage) is judged with: the Highway Code
# junction rulebooks, in the order a stage looks for the first one that defines its sentence
# (highway_code.le before validators.le: the vehicle's "can" is the Highway Code's own).
CURRENT_SET = ("highway_code.le", "monitors.le", "validators.le", "penalties.le", "liability.le")
