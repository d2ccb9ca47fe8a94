"""`gaps verify`: recompute the hash chains, Merkle roots and checkpoints, check the cached state
snapshots and the cached index of where road users were against the events, and name the first
event, snapshot or box that does not match (exit 1)."""
from __future__ import annotations

from pathlib import Path
from typing import Callable, Optional

import typer

from cli.app import open_existing, print_json, require_run
from cli.options import DbOption, JsonOption, RunOption
from cli.progress import stderr_progress
from cli.safe_text import printable
from cli.tables import text_or_null
from store import Store


def verify(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
           json_out: bool = JsonOption,
           with_snapshots: bool = typer.Option(
               True, "--snapshots/--no-snapshots",
               help="Also re-fold each run and name the cached state snapshots (and boxes of where road users "
                    "were) that differ from its events.")) -> None:
    """Check the hash chains, Merkle roots, checkpoints and cached snapshots against the events.

    Exit 1 if anything does not match, naming the first event (or snapshot) that does not; 2 for
    a usage error such as a missing store or run. Snapshots, and the index of where each road user
    was, live in the cache beside the store and are not evidence (nothing chains them), but scenes
    and verdicts read state and find the road users near a junction from them, so
    verify checks them too unless told --no-snapshots: nothing read can change a verdict without
    verify failing. Deleting the cache is safe; it is rebuilt from the events.
    """
    wrong: dict[str, list] = {}
    misplaced: dict[str, list] = {}
    with open_existing(db) as store:
        require_run(store, run)
        with stderr_progress("verifying") as progress:
            report = store.verify(run, progress)
        if with_snapshots:
            wrong = _wrong_snapshots(store, [r["run"] for r in report.runs])
            misplaced = _wrong_presence(store, [r["run"] for r in report.runs])
    ok = report.ok and not any(wrong.values()) and not any(misplaced.values())
    if json_out:
        print_json({**report.as_dict(), "ok": ok,
                    **({"snapshots": wrong, "presence": misplaced} if with_snapshots else {})})
    else:
        _print_report(report, wrong, with_snapshots)
        _print_presence(misplaced)
    raise typer.Exit(0 if ok else 1)


def _print_report(report, wrong: dict[str, list], with_snapshots: bool) -> None:
    for r in report.runs:
        typer.echo(f"{printable(r['run'])}: {r['events']} events, chain {'ok' if r['ok'] else 'BROKEN'}, "
                   f"head {r['head']}")
    if report.problem:
        p = report.problem
        typer.echo(f"FAILED at run {text_or_null(p['run'])} src {text_or_null(p['src'])} seq {p['seq']} "
                   f"(chain position {p['chain_pos']}): {printable(p['what'])}")
    else:
        typer.echo("verified: every chain and checkpoint matches")
    for name, positions in wrong.items():
        if positions:
            t, seq, src = positions[0]
            typer.echo(f"SNAPSHOTS WRONG in run {text_or_null(name)}: {len(positions)} differ from the events, "
                       f"the first after src {text_or_null(src)} seq {seq} (t {t}); they are a cache: "
                       "clearing them is safe")
    if with_snapshots and not any(wrong.values()):
        typer.echo("snapshots: every state snapshot matches its events")


def _wrong_snapshots(store: Store, runs: list[str]) -> dict[str, list[list]]:
    """Per run, the positions [t, seq, src] of the snapshots that differ from a fresh fold."""
    from store import check_snapshots
    return _per_run("checking snapshots", runs, lambda name: check_snapshots(store, name))


def _per_run(label: str, runs: list[str], check: Callable[[str], list]) -> dict[str, list[list]]:
    """Each run's wrong entries (as lists, for JSON), with a progress bar on a terminal."""
    with stderr_progress(label) as progress:
        wrong = {}
        for i, name in enumerate(runs):
            wrong[name] = [list(entry) for entry in check(name)]
            if progress is not None:
                progress(i + 1, len(runs))
    return wrong


def _print_presence(misplaced: dict[str, list]) -> None:
    for name, boxes in misplaced.items():
        if boxes:
            src, bucket = boxes[0]
            typer.echo(f"PRESENCE INDEX WRONG in run {text_or_null(name)}: {len(boxes)} boxes differ from the "
                       f"events, the first of src {text_or_null(src)} in bucket {bucket}; it is a cache: "
                       "clearing it is safe")


def _wrong_presence(store: Store, runs: list[str]) -> dict[str, list[list]]:
    """Per run, the [src, bucket] of the cached boxes of where road users were that differ from
    the events (store/presence.py)."""
    from store import check_presence
    return _per_run("checking where road users were", runs, lambda name: check_presence(store, name))
