"""The moment of the act a potential violation is about, in a vehicle's passage.

The law judges acts (DESIGN "Reasoning"): proceeding beyond the stop line on red, entering from
a Stop line without having stopped, entering when giving way would not let the main-road traffic
pass unhindered. A monitor may record a potential violation before the act (a car still moving
near a red light) or after it (in the junction, clearing it); the derived facts are taken at the
act itself, so that a car that then crosses is judged on its crossing and one that stops behind
the line on its stop. Speeding and stopping in a box are judged when recorded.
"""
from __future__ import annotations

from .history import STOPPED_MPS
from .history import Passage

# What other rooms take from here (tests/architecture/test_walls.py): the passage of an act, so that the
# report's act timeline draws the passage the judge measured (explain/act_data.py)
__all__ = ["of"]

SECOND = 1_000_000_000
NEAR_S = 5.0          # a passage this far (in time) from a moment is still the one of its act
SPEEDING = "exceed the speed limit"
BOX = "enter the box junction"
PASSAGE = "junction passage"     # the act of a junction rule: one passage (model.Act)


def of(passage: Passage | None, t: int) -> Passage | None:
    """The passage if the moment falls in it (or within NEAR_S of it), else None: a passage
    far from the moment is another visit to a junction, and no evidence of this act."""
    if passage is None:
        return None
    near = int(NEAR_S * SECOND)
    return passage if passage.start - near <= t <= passage.end + near else None


def moment(passage: Passage, t: int, action: str) -> int:
    """When the act of `action` recorded (or re-derived) at t happened in the passage."""
    if action == SPEEDING:
        return t
    if action == BOX:
        still = [s.t for s in passage.samples if s.t >= t and s.x is not None and s.y is not None and s.speed_mps is not None
                 and s.speed_mps <= STOPPED_MPS and passage.junction.in_box(s.x, s.y)]
        return still[0] if still else t
    if passage.crossing is not None and t < passage.crossing.t:
        return passage.crossing.t
    if passage.crossing is None and passage.entered is not None and t < passage.entered.t:
        return passage.entered.t
    return t


def moments(passage: Passage) -> tuple[tuple[str, int], ...]:
    """The passage's moments an investigator places the act by, in time order: standing still
    before the line, crossing it, entering and leaving the junction."""
    found = [("stood still before the line", s.first.t) for s in passage.standstills if s.to_line_m is not None
             and s.to_line_m >= -1.0]
    found += [("moved off", s.last.t) for s in passage.standstills if s.to_line_m is not None and s.to_line_m >= -1.0
              and (passage.crossing is None or s.last.t <= passage.crossing.t)]
    if passage.crossing is not None:
        found.append(("crossed the stop line", passage.crossing.t))
    if passage.entered is not None:
        found.append(("entered the junction", passage.entered.t))
    if passage.left is not None:
        found.append(("left the junction", passage.left.t))
    return tuple(sorted(found, key=lambda m: m[1]))
