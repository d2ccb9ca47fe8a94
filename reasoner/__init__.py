"""Reasoning over recorded runs: the LE rulebooks, the Prolog engine, scenarios and verdicts.

The public entry point is `reasoner.open(path)` (docs/api.md): a read-only `Case` whose answers
are the typed values below. Beside it, what the command line needs and a script may too: the
time forms (reasoner/when.py), the LE tool chain on one document (`gaps rules`) and the
regression (`gaps regress`, docs/regress.md: `reasoner.regression`, and the sub-face
`reasoner.regress` for its parts). Every other room reaches the reasoner through
these names, and for the parts a room needs beyond them, through a few module faces (each
module's `__all__`: docs/design.md, "Rooms and their faces"): `reasoner.model`, `.verdicts`,
`.vocabulary`, `.when`, `.wording`, `.scene`, `.timelines`, `.acts` for explain's renderings,
`.onboard` for the simulation's agents asking the law, and the sub-faces `reasoner.history` and
`reasoner.regress`. The modules below them are the reasoner's own
(tests/architecture/test_walls.py). Importing this package does not start Prolog; the engine
starts on first use.
"""
from .api import SOURCES, VERDICTS, Case, NoSuchIncident, open, regression  # noqa: A004
from .bundled import RULES_DIR
from .chain_status import ChainStatus
from .engine import QuestionError
from .explanation import Counterfactual, Explanation
from .le.errors import LEError
from .model import Control, Finding, Incident, Liability, Margin, Penalty
from .scene import Scene, SceneError
from .toolchain import (Answered, RulebookCheck, RulebookTests, ToolchainError, ask_rulebook, check_rulebook,
                        prolog_text, verify_rulebooks)
from .when import (DurationError, TimeError, format_duration, format_seconds, format_time_short, parse_duration,
                   parse_time)

# ChainStatus is Case.chain's answer and Counterfactual a part of Case.explanation's (explain words both)
__all__ = ["RULES_DIR", "SOURCES", "VERDICTS", "Answered", "Case", "ChainStatus", "Control", "Counterfactual",
           "DurationError", "Explanation", "Finding", "Incident", "LEError", "Liability", "Margin", "NoSuchIncident",
           "Penalty", "QuestionError", "RulebookCheck", "RulebookTests", "Scene", "SceneError", "TimeError",
           "ToolchainError", "ask_rulebook", "check_rulebook", "format_duration", "format_seconds", "format_time_short",
           "open", "parse_duration", "parse_time", "prolog_text", "regression", "verify_rulebooks"]
