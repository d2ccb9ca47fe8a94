"""`gaps demo`: sim_replay → Zenoh → ingest → store → reasoner → explain, on the paper's run.

Only composition lives here: each step is a call into the room that owns it.
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import db_path, fail, open_existing
from cli.incidents import show_incidents
from cli.local_ingest import publish_through_zenoh
from cli.progress import stderr_progress
from cli.safe_text import printable
from cli.options import DbOption, JsonOption
from explain import write_report
from reasoner import Case, format_seconds


def demo(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         report: Optional[Path] = typer.Option(
             None, "--report", help="Where to write the HTML report (default: gaps-report.html beside the store; "
                                    ".md or .json by suffix)."),
         paper: bool = typer.Option(False, "--paper", help="Replay the paper's two hand-written scenarios "
                                    "(section 7.2) instead of simulating."),
         overwrite: bool = typer.Option(False, "--overwrite", help="Replace the report of an earlier demo without "
                                        "asking.")) -> None:
    """Simulate the paper's junctions on SUMO, store, judge and explain the incidents, write a report.

    A seeded mix of road users, published over Zenoh into the store. The run holds a car running
    the red (punishable), an ambulance on a call crossing it (mitigated), an automated car whose
    camera misread the light (its ASDE liable) and a Stop line run; each is explained in full,
    every other incident listed in a line.

    An earlier demo's report is never replaced silently: on a terminal the demo asks first, and
    writes beside it if told no; elsewhere it writes beside it (gaps-report-2.html, ...) and says
    so, so that `make demo` runs again as it ran first. --overwrite replaces it.
    """
    path = db_path(db)
    target = report or path.parent / "gaps-report.html"
    earlier = None
    if target.exists() and report is None and not overwrite and not _may_replace(target):
        earlier, target = target, _beside(target)
    replacing = target.exists()
    if paper:
        from sim_replay import paper_run
        events = paper_run()
        run = events[0]["run"]
        totals, _ = publish_through_zenoh(path, events)
        if not json_out:
            typer.echo(f"Published {len(events):,} events of run {run} over Zenoh; stored {totals['stored']:,}, "
                       f"duplicates {totals['duplicates']:,}, rejected {totals['rejected']:,} → {path}\n")
    else:
        run = _simulate(path, json_out)
    with open_existing(path) as store:
        case = Case(store)              # judged once, for the listing and the report
        if paper or json_out:
            show_incidents(case, run, json_out, explain=True)
        else:
            _tour(case, run)
        try:
            written = write_report(case, run, target)
        except OSError as exc:
            fail(f"cannot write the report to {target}: {exc.strerror or exc}")
    again = " (replaced the earlier report)" if replacing else f" (beside the earlier {earlier.name})" if earlier else ""
    typer.echo(f"Report of run {run}: {written.resolve()}{again} (open it in a browser; `gaps report --run {run} -o FILE "
               "--pdf` prints a PDF)", err=json_out)


def _may_replace(target: Path) -> bool:
    """Whether the user, asked on a terminal, lets this demo replace an earlier report; where
    nobody can answer, no."""
    import sys
    if not (sys.stdin.isatty() and sys.stdout.isatty()):
        return False
    return typer.confirm(f"{target} exists (an earlier report): replace it? (no: this one is written beside it)",
                         default=False, err=True)


def _beside(target: Path) -> Path:
    """The first free name beside an earlier report: gaps-report-2.html, gaps-report-3.html, ..."""
    n = 2
    while (found := target.with_name(f"{target.stem}-{n}{target.suffix}")).exists():
        n += 1
    return found


def _simulate(path: Path, json_out: bool) -> str:
    """The demo's simulation, published into the store; its summary on stdout (stderr with --json)."""
    from sim_replay import DEMO, Simulation
    with stderr_progress("simulating the paper's junctions on SUMO") as bar:
        simulation = Simulation(DEMO, (lambda done, total: bar(int(done), int(total))) if bar else None)
        totals, _ = publish_through_zenoh(path, simulation.batches())
    s = simulation.summary
    assert s is not None                # its batches are run: the summary is made
    typer.echo(f"Simulated the paper's junctions on SUMO (run {DEMO.run}, seed {DEMO.seed}): {format_seconds(s.world_s, 3)} of "
               f"world time, {s.vehicles} vehicles, {s.pedestrians} pedestrians; {s.events:,} events, "
               f"{s.rulebook_queries:,} rulebook queries, {s.potential_violations} potential violations "
               f"recorded by the monitors on line.\n"
               f"Published over Zenoh; stored {totals['stored']:,}, duplicates {totals['duplicates']:,}, "
               f"rejected {totals['rejected']:,} → {path}\n", err=json_out)
    return DEMO.run


def _tour(case: Case, run: str) -> None:
    """Every incident in a line, then the featured ones explained in full."""
    from explain import acts_summary, explanations, featured, incident_line
    with stderr_progress("judging the recorded potential violations and the measured acts") as progress:
        found = case.numbered(run, progress=progress)
    typer.echo(f"{len(found)} incidents in run {run}, {acts_summary([inc for _, inc in found])} "
               f"(`gaps incidents --run {run}`; `gaps explain --run {run} N` explains one):")
    for n, inc in found:
        typer.echo(printable(incident_line(inc, n)))
    for feature, hit in featured(found):
        typer.echo(f"\n━━ {feature.title} ━━")
        if hit is None:
            typer.echo("none in this run")
        else:
            typer.echo("\n".join(explanations(case, [hit])))
