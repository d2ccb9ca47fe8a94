"""`gaps regress`: judge logged runs under new rulebooks and the baseline, and say what changed."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli import completion
from cli.app import db_path, fail, open_existing, print_json, writable_output
from cli.options import DbOption, JsonOption
from cli.progress import stderr_progress
from cli.safe_text import printable


def regress(recordings: Optional[list[Path]] = typer.Argument(
                None, metavar="FILES.mcap", help="Recordings (MCAP or JSONL) to regress straight from, "
                                                      "nothing prepared: every run in each."),
            rules: Optional[list[Path]] = typer.Option(
                None, "--rules", metavar="FILE.le…", help="The new rulebook: a .le file or a directory of them (repeatable)."),
            baseline: Optional[list[Path]] = typer.Option(
                None, "--baseline", metavar="in-force|OLD.le…", help="What to compare with: `in-force` (default: each run's own rulebooks, "
                                         "else the project's) or OLD .le files or directories (repeatable)."),
            run: Optional[list[str]] = typer.Option(None, "--run", help="A run to regress (repeatable).",
                                                  autocompletion=completion.runs),
            all_runs: bool = typer.Option(False, "--all", help="Regress every run of the store."),
            db: Optional[Path] = DbOption, json_out: bool = JsonOption,
            junit: Optional[Path] = typer.Option(None, "--junit", help="Also write JUnit XML here, a testcase per "
                                                                        "incident and decision."),
            golden: Optional[Path] = typer.Option(None, "--golden", help="Compare the golden runs of this file "
                                                                          "with their approved verdicts."),
            update_golden: bool = typer.Option(False, "--update-golden", help="Approve the judgement: write it "
                                                                              "into the --golden file."),
            workers: int = typer.Option(1, "--workers", min=1, help="Judge the runs in parallel on a local Dask "
                                                                     "cluster of this many worker processes."),
            scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Judge the runs on the Dask cluster "
                                                                                "of this scheduler (tcp://host:8786).")
            ) -> None:
    """Re-judge logged runs under new rulebooks and show what changed, and why.

    Every incident and recorded vehicle decision of the runs is judged under the baseline and
    under --rules: verdicts flipped, incidents new or gone, penalties or liability changed,
    decisions the new rules forbid or allow, each with the changed rules its proofs used; with
    --baseline OLD the rule change report comes first. Exit 0 when nothing changed, 1 when
    something did, 2 on a mistake (a file no stage uses, an unknown run, LE that does not parse).
    Runs are judged one after another, or in parallel on Dask with --workers N or --scheduler.

    A recording judged once is kept by the digest of its bytes in the user's cache home
    ($XDG_CACHE_HOME/mind-the-gaps/recordings, at most $GAPS_RECORDINGS_CACHE_MB, 4096 by
    default; 0 keeps none): regressing the same file again reads none of its events.
    """
    from reasoner import regression
    from reasoner.regress import Cluster, check_golden, junit_xml, lines, regress_recordings
    from store import write_bytes
    writable_output(junit, db)
    writable_output(golden if update_golden else None, db)

    rule_args = [str(p) for p in rules or []]
    on = Cluster(workers, scheduler)
    if golden is not None:
        if recordings or not on.in_process:
            fail("--golden judges its own runs in one process: leave out FILES, --workers and --scheduler")
        result = check_golden(golden, lambda: open_existing(db), rule_args, run or [], update_golden)
    else:
        if update_golden:
            fail("--update-golden needs --golden FILE")
        if not rule_args:
            fail("name the new rulebook with --rules FILE.le (or a directory)")
        if recordings and (run or all_runs):
            fail("regress either recordings (FILES.mcap) or a store's runs (--run R, --all), not both")
        if not recordings and bool(run) == all_runs:
            fail("name the runs with --run R (repeatable) or --all, or give recordings (FILES.mcap)")
        base = [str(p) for p in baseline or []]
        base_arg = None if base in ([], ["in-force"]) else base
        with stderr_progress("judging runs") as bar:
            progress = (lambda _label, done, total: bar(done, total)) if bar else None
            if recordings:
                result = regress_recordings(recordings, rule_args, base_arg, cluster=on, progress=progress)
            else:
                open_existing(db).close()            # the store's own checks, said before any judging
                result = regression(db_path(db), rule_args, base_arg, None if all_runs else run, cluster=on,
                                    progress=progress)
    if junit is not None:
        write_bytes(junit, junit_xml(result), [db_path(db)])
    if json_out:
        print_json(result.to_json())
    else:
        for line in lines(result):
            typer.echo(printable(line))
        if update_golden:
            typer.echo(printable(f"Approved: {golden} now holds this judgement."))
    raise typer.Exit(1 if result.changed and not update_golden else 0)
