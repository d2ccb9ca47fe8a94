"""The law on board: what the simulation's agents ask the rulebooks with, as they drive and watch.

A simulated vehicle asks highway_code.le whether it can enter the junction on what it perceives,
and a monitor asks monitors.le whether what it observes potentially violates a rule; the paper's
run asks the paper's rulebook the same way (sim_replay/asking.py, sim_replay/paper.py). They ask
live, one question at a time, where the judge asks of a whole record afterwards, so they need
the engine and the rulebooks themselves, not a `Case`: this face hands out exactly that, and
nothing of the judge. The names stay defined where they live (the engine, the bundled
rulebooks, the fact reader, the shaper, the LE sentence reader); the simulation reaches them
only here (tests/architecture/test_walls.py), and explain never does.
"""
from __future__ import annotations

from .bundled import CURRENT_SET, PAPER, bundled
from .engine import Answer, Rulebook, enrich, get_engine, sha256_text
from .facts import FactReader
from .le.sentences import constant, parse_fact
from .shapes import Shaper

# Who takes each: the rulebooks a run records (CURRENT_SET, PAPER, bundled, sha256_text: asking.py,
# paper.py); the engine and a loaded rulebook (get_engine, Rulebook), its answer and that answer's
# proof as DESIGN's tree (Answer, enrich: asking.py); facts read with a rulebook's templates, never as
# Prolog text (FactReader: asking.py; parse_fact: paper.py); a question asked once per shape of its
# facts (Shaper, and constant for the vehicle's own name in it: asking.py)
__all__ = ["CURRENT_SET", "PAPER", "Answer", "FactReader", "Rulebook", "Shaper", "bundled", "constant", "enrich",
           "get_engine", "parse_fact", "sha256_text"]
