"""`gaps verify`: recompute the hash chains, Merkle roots and checkpoints, check the cached state
snapshots and the cached index of where road users were against the events, count the signed
events and check their signatures against a public keys file, and name the first event, snapshot,
box or signature that does not match (exit 1)."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import open_existing, print_json, require_run
from cli.options import DbOption, JsonOption, RunOption
from cli.progress import stderr_progress
from cli.safe_text import printable
from cli.tables import text_or_null
from store import Problem, SignatureCount, VerifyReport, check_store


def verify(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
           json_out: bool = JsonOption,
           with_snapshots: bool = typer.Option(
               True, "--snapshots/--no-snapshots",
               help="Also re-fold each run and name the cached state snapshots (and boxes of where road users "
                    "were) that differ from its events."),
           keys_file: Optional[Path] = typer.Option(
               None, "--keys", metavar="KEYS", help="Check every signed event against the keys this public keys "
                                                     "file trusts for its source (`gaps keys public`)."),
           all_signed: bool = typer.Option(
               False, "--all-signed", help="Fail (exit 1) if any event is unsigned, too."),
           against: Optional[Path] = typer.Option(
               None, "--against", metavar="HEADS", help="Check the store against the signed tree heads of this "
                                                        "witness file (`gaps serve --witness`): a run cut back, "
                                                        "rewritten or deleted fails."),
           checkpoint_key: Optional[Path] = typer.Option(
               None, "--key", metavar="PUB", help="The checkpoint key's public file (`gaps keys checkpoint`; "
                                                  "your copy, which records each run's first signed head): every "
                                                  "run must end on a checkpoint signed by it, every checkpoint "
                                                  "since the run's first signed head too, and so must the heads "
                                                  "of --against.")) -> None:
    """Check the hash chains, Merkle roots, checkpoints and cached snapshots against the events.

    Exit 1 if anything does not match, naming the first event (or snapshot) that does not; 2 for
    a usage error such as a missing store or run. Snapshots, and the index of where each road user
    was, live in the cache beside the store and are not evidence (nothing chains them), but scenes
    and verdicts read state and find the road users near a junction from them, so
    verify checks them too unless told --no-snapshots: nothing read can change a verdict without
    verify failing. Deleting the cache is safe; it is rebuilt from the events. Cache entries that
    do not carry their seal (written by something other than gaps) are never used, and are named in
    a WARNING (exit 0: the evidence and every verdict stand).

    Signed events are counted; with --keys each signature is checked against the keys trusted for
    its event's source, and an invalid one (altered, forged, a key not trusted for that source)
    fails, naming the first. A signature proves its event even where the chain is broken.

    A store agrees with itself after a consistent rewrite too; --against and --key check it
    against what is kept outside it: the tree heads of a witness file (each run at least as long
    as each head, its first events giving the head's Merkle root, the heads following one another)
    and the checkpoint key (with the runs' first signed heads its public file records). Then each
    run's stored events must all be proven by one of them: the report says, per run, how many
    events the witness proves and how many the key does (docs/guarantees.md).
    """
    keys = _trusted(keys_file)
    heads, public, recorded = _anchors(against, checkpoint_key)
    with open_existing(db) as store:
        require_run(store, run)
        found = check_store(store, run, keys=keys, heads=heads, heads_file=against, public=public,
                            recorded=recorded, snapshots=with_snapshots, all_signed=all_signed, bars=stderr_progress)
    if json_out:
        print_json(found.to_json())
    else:
        _print_report(found.report, found.wrong_snapshots or {}, with_snapshots)
        _print_presence(found.misplaced or {})
        _print_signatures(found.report.signatures, all_signed)
        _print_tampering(found.tampering)
        _print_anchors(against, found.anchored.heads, found.anchored.key)
        _print_proven(found.anchored.runs)
    raise typer.Exit(0 if found.ok else 1)


def _trusted(keys_file: Optional[Path]):
    """The public keys file, loaded (a KeysError, exit 2, names what is wrong with it); None without one."""
    if keys_file is None:
        return None
    from store.keys import TrustedKeys
    return TrustedKeys.load(keys_file)


def _anchors(against: Optional[Path], checkpoint_key: Optional[Path]):
    """The witness file's heads, the checkpoint public key and the runs' first signed heads its
    file records, read (exit 2 naming what is wrong)."""
    from store.keys import load_public, read_heads, recorded_heads
    heads = read_heads(against) if against is not None else []
    public = load_public(checkpoint_key) if checkpoint_key is not None else None
    recorded = recorded_heads(checkpoint_key, public) if checkpoint_key is not None and public is not None else []
    return heads, public, recorded


def _print_anchors(against: Optional[Path], outcomes: list, keyed) -> None:
    if against is not None:
        bad = [o for o in outcomes if not o.ok]
        runs = len({o.run for o in outcomes})
        if not bad:
            typer.echo(f"heads: {len(outcomes):,} tree heads of {runs} run(s) in {printable(str(against))} match "
                       f"the store ({_coverage(outcomes)})")
        for o in bad[:10]:
            typer.echo(f"HEAD FAILED: run {text_or_null(o.run)} at {o.size:,} events ({o.outcome}): {printable(o.what)}")
        if len(bad) > 10:
            typer.echo(f"... and {len(bad) - 10:,} more heads failed (--json lists them all)")
    if keyed is not None:
        if keyed.ok:
            typer.echo(f"checkpoint key {keyed.key}: {keyed.signed:,} checkpoints signed by it, every run ends on "
                       f"one and every checkpoint since a run's first signed head is ({keyed.unsigned_before:,} "
                       "before those unsigned)")
        else:
            typer.echo(f"CHECKPOINT KEY {keyed.key} FAILED: {printable(keyed.problem.what)}")
        if keyed.absent:
            shown = ", ".join(printable(name) for name in keyed.absent[:10]) + (" ..." if len(keyed.absent) > 10
                                                                                  else "")
            typer.echo(f"the key file records {len(keyed.absent)} run(s) this store does not hold: {shown} (deleted, "
                       "or signed into another store with this key: the witness of this store's ingest tells)")


def _print_proven(proofs: list) -> None:
    """Per run, what the witness and the key prove of its stored events."""
    for p in proofs:
        by = [f"{p.witnessed:,} by the witness's heads" if p.witnessed is not None else None,
              f"{p.signed:,} by checkpoints signed by the key" if p.signed is not None else None]
        said = f"{p.events:,} events; proven: " + ", ".join(b for b in by if b)
        if p.ok:
            typer.echo(f"run {printable(p.run)}: {said}")
        else:
            typer.echo(f"RUN NOT PROVEN: {printable(p.run)}: {said}: {printable(p.what)}")


def _coverage(outcomes: list) -> str:
    """What the heads that matched cover besides the events: heads written before v8 record no
    wire part, and parts written before the rulebooks were chained record no rulebooks' end."""
    older = sum(o.wire != "checked" for o in outcomes)
    unbooked = sum(o.wire == "checked" and o.rulebooks != "checked" for o in outcomes)
    if not older and not unbooked:
        return "each with the wire tables' and the rulebooks' ends"
    said = [f"{older:,} of them written before v8: those cover the events, not the wire tables"] if older else []
    if unbooked:
        said.append(f"{unbooked:,} with the wire tables' ends but not the rulebooks' (written before those were "
                    "recorded)")
    return "; ".join(said)


def _print_signatures(s: SignatureCount | None, all_signed: bool) -> None:
    if s is None:
        return
    counts = f"{s.signed:,} signed, {s.unsigned:,} unsigned"
    if not s.checked:
        typer.echo(f"signatures: {counts} (not checked: give --keys KEYS)")
    elif not s.invalid:
        typer.echo(f"signatures: {counts}; every signature is valid ({s.keys})")
    else:
        typer.echo(f"signatures: {counts}; {s.valid:,} valid, {s.invalid:,} INVALID ({s.keys})")
        if s.first_invalid is not None:
            typer.echo(f"INVALID SIGNATURE at {_where(s.first_invalid)}")
    if all_signed and s.unsigned:
        typer.echo(f"UNSIGNED: {s.unsigned:,} events carry no signature, and --all-signed asks that all do")


def _where(p: Problem) -> str:
    """Where an event's problem is, and what it is."""
    return (f"run {text_or_null(p.run)} src {text_or_null(p.src)} seq {p.seq} "
            f"(chain position {p.chain_pos}): {printable(p.what)}")


def _print_report(report: VerifyReport, wrong: dict[str, list], with_snapshots: bool) -> None:
    for r in report.runs:
        typer.echo(f"{printable(r.run)}: {r.events:,} events, chain {'ok' if r.ok else 'BROKEN'}, "
                   f"head {r.head}")
    if report.problem and report.problem.run is None:  # the file or a rulebook, not an event
        typer.echo(f"FAILED: {printable(report.problem.what)}")
    elif report.problem:
        typer.echo(f"FAILED at {_where(report.problem)}")
    else:
        typer.echo("verified: every chain and checkpoint matches, and the file passes SQLite's integrity check")
    for name, positions in wrong.items():
        if positions:
            t, seq, src = positions[0]
            typer.echo(f"SNAPSHOTS WRONG in run {text_or_null(name)}: {len(positions)} differ from the events, "
                       f"the first after src {text_or_null(src)} seq {seq} (t {t}); they are a cache: "
                       "clearing them is safe")
    if with_snapshots and not any(wrong.values()):
        typer.echo("snapshots: every state snapshot matches its events")


def _print_presence(misplaced: dict[str, list]) -> None:
    for name, boxes in misplaced.items():
        if boxes:
            src, bucket = boxes[0]
            typer.echo(f"PRESENCE INDEX WRONG in run {text_or_null(name)}: {len(boxes)} boxes differ from the "
                       f"events, the first of src {text_or_null(src)} in bucket {bucket}; it is a cache: "
                       "clearing it is safe")


def _print_tampering(tampering) -> None:
    """A warning, not a failure: such entries are never read (they are dropped and rebuilt from the
    events), so the evidence and every verdict stand; but someone wrote them into the cache file."""
    if tampering.ok:
        return
    dropped = ", ".join(f"{n} {table}" for table, n in sorted(tampering.dropped_by_reads.items()))
    typer.echo(f"WARNING: the cache file beside the store holds {tampering.count()} entries that do not carry "
               "their seal (altered since gaps wrote them, or written by something else"
               + (f"; dropped by reads: {dropped}" if dropped else "")
               + "); they are never used, and are rebuilt from the events")
    for run, positions in tampering.snapshots.items():
        typer.echo(f"  run {text_or_null(run)}: {len(positions)} state snapshot(s), the first at {positions[0]}")
    for run, what in tampering.presence.items():
        typer.echo(f"  run {text_or_null(run)}: {'; '.join(what)}")
    if tampering.verifications:
        typer.echo(f"  {len(tampering.verifications)} recorded verification result(s)")
    for run, what in tampering.derived.items():
        typer.echo(f"  run {text_or_null(run)}: {len(what)} derived measurement(s), the first: {what[0]}")
