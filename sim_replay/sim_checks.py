"""What `gaps sim` settles before it simulates (issue 38: the command parses and prints, the room
decides): the files a `--map`, `--routes` and `--monitors` name, read into the run's config and
checked (a network the audit cannot judge, or routes it cannot carry, is refused with the
reason), and one run, one producer (a simulation never stores into a run a store already holds,
nor replaces a ground truth file). Each refusal is an OwnFilesError or a RunTaken, exit 2, naming
what to change.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from store import GapsError, Store, StoreError

from .maps import map_files
from .own_network import OwnFilesError, check, own_files
from .sim_config import SimConfig


class RunTaken(GapsError):
    """The run (or its ground truth file) is another producer's already."""


def with_files(config: SimConfig, map_: str, routes: tuple[Path, ...], monitors: Path | None) -> SimConfig:
    """`config` with the files --map, --routes and --monitors name, checked before anything is
    written: the vehicles and pedestrians the routes carry replace the drawn counts."""
    try:
        own = own_files(map_, routes, monitors)
        for path in (*routes, *((monitors,) if monitors else ())):
            if not path.is_file():
                raise OwnFilesError(f"no such file: {path}")
        net = own.net if own else map_files(map_).net
        counts = check(net, own.routes if own else routes, config) if own or routes else None
    except FileNotFoundError as exc:
        raise OwnFilesError(str(exc)) from None
    changes: dict[str, Any] = {"map": own.net.name, "net": str(own.net), "routes": tuple(map(str, own.routes)),
                               "monitors": str(own.monitors) if own.monitors else None} if own else \
        {"map": map_, "routes": tuple(map(str, routes)), "monitors": str(monitors) if monitors else None}
    if counts is not None:
        changes.update(vehicles=counts[0], pedestrians=counts[1])
    return dataclasses.replace(config, **changes)


def refuse_second_producer(run: str, store_file: Path | None, truth_file: Path) -> None:
    """RunTaken if the store already holds events of `run` (another seed's events would mix with
    the first's, and its ground truth replace theirs) or `truth_file` exists."""
    if store_file is not None and store_file.is_file():
        try:
            with Store.open_read_only(store_file) as held:
                events = held.count(run)
        except StoreError:
            events = 0          # not a store we can read: the ingest says why when it opens it
        if events:
            raise RunTaken(f"run {run} already holds {events:,} events in {store_file}: a run holds one producer's "
                           f"events, so a new simulation is never mixed into it; give another --run or another --db")
    if truth_file.exists() or truth_file.is_symlink():
        raise RunTaken(f"the ground truth {truth_file} already exists (an earlier simulation's?): it is never "
                       "replaced; remove it, or give --truth FILE or another --run")
