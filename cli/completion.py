"""Shell completion of run names and incident numbers (`gaps --install-completion`).

A completion reads the store as every read command does, read-only, and with its cache in
memory, so that pressing Tab writes nothing anywhere: not the store, not the cache beside it. A
store that cannot be read completes nothing, silently: completion never prints an error into the
line being typed.
"""
from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Optional

import typer

from store import Store

IN_MEMORY = ":memory:"      # the store's cache kept in memory (store.Store's cache_at)


def runs(ctx: typer.Context, incomplete: str) -> list[str]:
    """The store's run ids starting with what was typed."""
    with _store(ctx) as store:
        return [] if store is None else [r.run for r in store.runs() if r.run.startswith(incomplete)]


def incidents(ctx: typer.Context, incomplete: str) -> list[tuple[str, str]]:
    """The numbers `gaps explain --run R N` takes, each with its incident in a few words; the run
    must be typed first (--run R)."""
    run = ctx.params.get("run")
    with _store(ctx) as store:
        if store is None or not run:
            return []
        from reasoner import Case
        found = Case(store).numbered(run)
    numbered = [(str(n), f"{inc.id}: vehicle {inc.vehicle}, {inc.action}, {inc.verdict}") for n, inc in found]
    return [(n, said) for n, said in numbered if n.startswith(incomplete)]


@contextmanager
def _store(ctx: typer.Context) -> Iterator[Optional[Store]]:
    path = Path(ctx.params.get("db") or os.environ.get("GAPS_DB") or "gaps.db")
    try:
        store = Store(path, read_only=True, cache_at=IN_MEMORY) if path.is_file() else None
    except Exception:       # not a store, or one we cannot read: nothing to offer
        store = None
    try:
        yield store
    except Exception:
        pass
    finally:
        if store is not None:
            store.close()
