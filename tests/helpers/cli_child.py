"""Running `gaps` commands one after another in a child process, each as a user would type it, and
recording how each ended: its exit code, what it printed, and a traceback if one escaped.

    python -m tests.helpers.cli_child < cases.json > results.json

Input: a JSON list of cases, each a list of commands (argument lists). Output: per case, per
command, {"code": int | "exception", "out": str, "err": str}. One process for all the cases:
starting `gaps` costs a second or more on a loaded machine, and SWI-Prolog starts once.
"""

from __future__ import annotations

import contextlib
import io
import json
import sys
import traceback


def run(args: list[str]) -> dict:
    from cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            sys.argv = ["gaps", *args]
            main()
            code: int | str = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except BaseException:  # what the test looks for: nothing may escape a command
            err.write(traceback.format_exc())
            code = "exception"
    return {"code": code, "out": out.getvalue(), "err": err.getvalue()}


if __name__ == "__main__":
    cases = json.load(sys.stdin)
    json.dump([[run(command) for command in case] for case in cases], sys.stdout)
