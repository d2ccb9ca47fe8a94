"""Pin the SWI-Prolog home before janus_swi starts the embedded engine.

janus_swi initialises Prolog as `swipl`; without SWI_HOME_DIR the library searches PATH, and
an older system `swipl` there makes it load a foreign boot file and abort with
"incompatible VM-signature".  The set-up records the home it built janus against in
`<venv>/gaps-swipl-home`; GAPS_SWIPL_HOME overrides it.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from store import GapsError

HOME_FILE = Path(sys.prefix) / "gaps-swipl-home"
MIN_VERSION = 90112


class PrologUnavailable(GapsError, RuntimeError):
    """SWI-Prolog cannot be started; the message says how to fix the set-up."""

    exit_code = 3


def swipl_home() -> str:
    home = os.environ.get("GAPS_SWIPL_HOME")
    if not home and HOME_FILE.is_file():
        home = HOME_FILE.read_text(encoding="utf-8").strip()
    if not home:
        raise PrologUnavailable(
            f"no SWI-Prolog home recorded in {HOME_FILE} (or GAPS_SWIPL_HOME); run `make setup`")
    if not Path(home, "boot.prc").is_file():
        raise PrologUnavailable(f"{home} is not an SWI-Prolog home (no boot.prc); run `make setup`")
    return home


def import_janus():
    """Import janus_swi with the pinned home and check the engine is new enough."""
    os.environ["SWI_HOME_DIR"] = swipl_home()
    try:
        import janus_swi as janus
    except ImportError as exc:
        raise PrologUnavailable(f"janus_swi is not installed ({exc}); run `make setup`") from exc
    version = janus.query_once("current_prolog_flag(version, V)")["V"]
    if version < MIN_VERSION:
        raise PrologUnavailable(f"SWI-Prolog {version} is older than {MIN_VERSION}")
    return janus
