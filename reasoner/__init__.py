"""Reasoning over recorded runs: the LE rulebooks, the Prolog engine, scenarios and verdicts.

The public entry point is `reasoner.open(path)` (docs/api.md): a read-only `Case` whose answers
are the typed values below. Beside it, what the command line needs and a script may too: the
time forms (reasoner/when.py), the LE tool chain on one document (`gaps rules`) and the
regression (`gaps regress`, docs/regress.md: `reasoner.regression`, and the sub-face
`reasoner.regress` for its parts). Every other room reaches the reasoner through
these names; the modules below them are its own. Importing this package does not start Prolog;
the engine starts on first use.
"""
from .api import SOURCES, VERDICTS, Case, NoSuchIncident, open, regression  # noqa: A004
from .bundled import RULES_DIR
from .engine import QuestionError
from .explanation import Explanation
from .le.errors import LEError
from .model import Control, Finding, Incident, Liability, Margin, Penalty
from .scene import Scene, SceneError
from .toolchain import (Answered, RulebookCheck, RulebookTests, ToolchainError, ask_rulebook, check_rulebook,
                        prolog_text, verify_rulebooks)
from .when import (DurationError, TimeError, format_duration, format_seconds, format_time_short, parse_duration,
                   parse_time)

__all__ = ["RULES_DIR", "SOURCES", "VERDICTS", "Answered", "Case", "Control", "DurationError", "Explanation",
           "Finding", "Incident", "LEError", "Liability", "Margin", "NoSuchIncident", "Penalty", "QuestionError",
           "RulebookCheck", "RulebookTests", "Scene", "SceneError", "TimeError", "ToolchainError", "ask_rulebook",
           "check_rulebook", "format_duration", "format_seconds", "format_time_short", "open", "parse_duration",
           "parse_time", "prolog_text", "regression", "verify_rulebooks"]
