"""Reasoning over recorded runs: the LE rulebooks, the Prolog engine, scenarios and verdicts.

The public entry point is `reasoner.open(path)` (docs/api.md): a read-only `Case` whose answers
are the typed values below. Beside it, what the command line needs and a script may too: the
time forms (reasoner/when.py), the LE tool chain on one document (`gaps rules`) and the
regression (`gaps regress`, docs/regress.md). Every other room reaches the reasoner through
these names; the modules below them are its own. Importing this package does not start Prolog;
the engine starts on first use.
"""
from .api import SOURCES, VERDICTS, Case, NoSuchIncident, open  # noqa: A004
from .engine import QuestionError, enrich, get_engine
from .explanation import Explanation
from .le.document import parse_facts, parse_question
from .le.errors import LEError
from .le.expectations import ExpectationError
from .model import Control, Finding, Incident, Liability, Margin, Penalty
from .regress import Regression
from .regress import regress as regress_runs        # the module keeps the name `reasoner.regress`
from .regress_cluster import Cluster, regress_recordings, regress_store
from .regress_golden import check_golden
from .regress_junit import junit_xml
from .regress_text import lines as regression_lines
from .rules_verify import verify_file
from .scene import Scene, SceneError
from .when import (DurationError, TimeError, format_duration, format_seconds, format_time_short, parse_duration,
                   parse_time)

__all__ = ["SOURCES", "VERDICTS", "Case", "Cluster", "Control", "DurationError", "ExpectationError", "Explanation",
           "Finding", "Incident", "LEError", "Liability", "Margin", "NoSuchIncident", "Penalty", "QuestionError",
           "Regression", "Scene", "SceneError", "TimeError", "check_golden", "enrich", "format_duration",
           "format_seconds", "format_time_short", "get_engine", "junit_xml", "open", "parse_duration", "parse_facts",
           "parse_question", "parse_time", "regress_recordings", "regress_runs", "regress_store", "regression_lines",
           "verify_file"]
