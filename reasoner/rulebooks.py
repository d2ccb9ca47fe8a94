"""What the command line needs of a rulebook a user wrote: its errors, and a question or facts
written outside it, read with its templates (`gaps rules check`, `query`, `verify`).

The LE compiler (reasoner/le) is the reasoner's own part; the rooms outside it read a rulebook
through this face and the engine's (reasoner.engine), never the compiler's modules
(tests/architecture/test_walls.py), so the compiler can change its insides without them knowing.
"""
from __future__ import annotations

from .le.document import parse_facts, parse_question
from .le.errors import LEError
from .le.expectations import ExpectationError

__all__ = ["ExpectationError", "LEError", "parse_facts", "parse_question"]
