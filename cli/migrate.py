"""`gaps migrate SRC DST`: write a copy of an older store migrated to the current schema."""
from __future__ import annotations

from pathlib import Path

import typer

from cli.app import fail, print_json
from cli.options import JsonOption


def migrate(src: Path = typer.Argument(..., help="The store to migrate; it is read, never changed."),
            dst: Path = typer.Argument(..., help="The file to write the migrated copy to; must not exist."),
            json_out: bool = JsonOption) -> None:
    """Copy a store written by an older gaps to DST at the current schema; reading never migrates."""
    from store import migrate_copy
    try:
        report = migrate_copy(src, dst)
    except OSError as exc:
        fail(f"cannot migrate {src} to {dst}: {exc.strerror or exc}")
    if json_out:
        print_json(report.to_json())
        return
    typer.echo(f"migrated {report.src} (schema version {report.from_version}) → {report.dst} "
               f"(version {report.to_version}): {report.events:,} events; {report.src} is unchanged")
