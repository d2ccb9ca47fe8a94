"""A run's stored events as rows, in the order an export writes them.

Exports read the stored canonical text and write it as it is: parsing it into dicts and encoding
it again would only cost time (it is the hot loop of an export) and could not change a byte.

Two orders: "time" is (t, seq, src), the order Store.events reads; "chain" is the order the
events were appended, which is the order the run's hash chain covers them. Re-importing a file
written in chain order rebuilds the identical chain, so its heads can be checked against the
checkpoints exported with it; a file in time order rebuilds the same events, and the same heads
only when the run was stored in time order.
"""

from __future__ import annotations

from typing import Iterator, Literal, NamedTuple

from ..db import Store
from ..run_summary import RunSummary
from .errors import TransferError

Order = Literal["time", "chain"]
"""The order an export writes a run's events in, and a re-import appends them in."""
ORDERS: tuple[Order, ...] = ("time", "chain")
_ORDER_BY = {"time": "t, seq, src", "chain": "chain_pos"}


def order_of(name: str) -> Order:
    """The order of this name, or a TransferError naming the orders there are."""
    for order in ORDERS:
        if name == order:
            return order
    raise TransferError(f"unknown order {name!r}: use one of {', '.join(ORDERS)}")


class Row(NamedTuple):
    src: str
    seq: int
    t: int
    kind: str
    text: str  # the event's canonical JSON


def stored_rows(store: Store, run: str, order: str) -> Iterator[Row]:
    """Stream the run's events as rows; both orders are index scans, nothing is sorted in memory."""
    order = order_of(order)
    cursor = store.connection.execute(
        f"SELECT src, seq, t, kind, event FROM events WHERE run = ? ORDER BY {_ORDER_BY[order]}", (run,)
    )
    return (Row(*row) for row in cursor)


def run_summary(store: Store, run: str) -> RunSummary:
    """The run's summary from the store, or a TransferError naming the runs there are."""
    runs = store.runs()
    for summary in runs:
        if summary.run == run:
            return summary
    known = ", ".join(r.run for r in runs) or "none"
    raise TransferError(f"no run {run!r} in {store.path}; runs: {known}")


def chain_head(store: Store, run: str) -> str | None:
    """The hash stored with the run's last chained event: its chain head as the store has it
    (recomputing it is `gaps verify`'s job)."""
    row = store.connection.execute(
        "SELECT hash FROM events WHERE run = ? ORDER BY chain_pos DESC LIMIT 1", (run,)
    ).fetchone()
    return None if row is None else row[0]


def chain_keys(store: Store, run: str) -> Iterator[tuple[str, int, int]]:
    """(src, seq, t) of the run's events in chain order: what an MCAP export, written in time
    order, needs to tell an import the order to append them in."""
    cursor = store.connection.execute(
        "SELECT src, seq, t FROM events WHERE run = ? ORDER BY chain_pos", (run,)
    )
    return iter(cursor)
