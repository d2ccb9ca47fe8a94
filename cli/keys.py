"""`gaps keys`: Ed25519 keys for sources that sign their events, and the public keys file that
`gaps serve --require-signatures` and `gaps verify --keys` trust (store/keyfiles.py, docs/store.md)."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from cli.app import print_json
from cli.options import JsonOption, is_stdio

HELP = ("Make Ed25519 keys for sources to sign their events with, the public keys file that checks them, and the "
        "ingest's checkpoint key.")


def new(folder: Path = typer.Argument(..., help="The key folder (created if missing): FOLDER/ROLE/ID.key."),
        sources: list[str] = typer.Argument(..., help="Sources to make a key for, e.g. vehicle/173 monitor/m1."),
        json_out: bool = JsonOption) -> None:
    """Make a private key for each source in FOLDER and write FOLDER/public-keys.json for all its keys.

    A key that exists is never overwritten (exit 2). Keep FOLDER with the sources; give
    public-keys.json to the ingest and the investigators.
    """
    from store.keys import KeyFolder, key_id
    keys = KeyFolder(folder)
    for src in sources:
        keys.key_path(src)  # every name checked before any key is made
    made = [{"src": src, "path": str(keys.create(src)), "key": key_id(keys.public_key(src))} for src in sources]
    public = keys.write_public_keys()
    if json_out:
        print_json({"created": made, "public_keys": str(public)})
        return
    for entry in made:
        typer.echo(f"{entry['src']}: key {entry['key']} → {entry['path']}")
    typer.echo(f"public keys of {len(keys.sources())} source(s) → {public}")


def public(folder: Path = typer.Argument(..., help="The key folder."),
           output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of "
                                                 "FOLDER/public-keys.json; - for standard output.")) -> None:
    """Write the public keys file of every key in FOLDER: JSON {source: base64 Ed25519 public key}."""
    from store.keys import KeyFolder
    keys = KeyFolder(folder)
    if output is not None and is_stdio(output):
        typer.echo(json.dumps(keys.public_keys(), indent=2, sort_keys=True))
        return
    target = keys.write_public_keys(output)
    typer.echo(f"public keys of {len(keys.sources())} source(s) → {target}")


def checkpoint(path: Path = typer.Argument(..., help="Where to write the private key; its public half goes to "
                                                     "PATH.pub."),
               json_out: bool = JsonOption) -> None:
    """Make the checkpoint key that the ingest and imports sign checkpoints with, and PATH.pub for `gaps verify --key`.

    `gaps serve --checkpoint-key PATH` and `gaps import --checkpoint-key PATH` use it, and append each
    run's first signed head to PATH.pub: give investigators a copy of PATH.pub from the ingest's host
    (`gaps verify --key`), never one that travelled with the store. An existing key is never
    overwritten (exit 2). Keep PATH on the ingest's host only: whoever holds it can sign checkpoints
    over a rewritten store.
    """
    from store.keys import CheckpointKey, public_path_of
    key = CheckpointKey.create(path)
    made = {"path": str(path), "public": str(public_path_of(path)), "key": key.id}
    if json_out:
        print_json(made)
        return
    typer.echo(f"checkpoint key {key.id} → {path} (public half → {made['public']})")
