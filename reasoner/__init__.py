"""Reasoning over recorded runs: the LE rulebooks, the Prolog engine, scenarios and verdicts.

The public entry point is `reasoner.open(path)` (docs/api.md): a read-only `Case` whose answers
are the typed values below. Importing this package does not start Prolog; the engine starts on
first use.
"""
from .api import VERDICTS, Case, NoSuchIncident, open  # noqa: A004
from .explanation import Explanation
from .model import Control, Finding, Incident, Liability, Margin, Penalty
from .scene import Scene

__all__ = ["VERDICTS", "Case", "Control", "Explanation", "Finding", "Incident", "Liability", "Margin",
           "NoSuchIncident", "Penalty", "Scene", "open"]
