"""Tables on the terminal (rich), with every cell escaped: recorded text is shown, never obeyed.

An id (a run, a source) is what a reader copies into the next command, so it is never cut: its
column does not wrap, and on a terminal too narrow for it the other columns wrap first; where even
that is not enough, the table is drawn wider than the terminal rather than cut an id. Piped (not a
terminal) nothing wraps at all: every value is whole, for grep and for the next program.
"""
from __future__ import annotations

import io
import shutil
import sys
from typing import Any

from cli.safe_text import printable

IDS = frozenset({"run", "src"})     # the headers whose cells are ids, never cut
PIPED = 10_000                      # wide enough that rich wraps nothing


def table(*headers: str):
    from rich.table import Table
    drawn = Table()
    for header in headers:
        if header in IDS:
            drawn.add_column(header, no_wrap=True, overflow="ignore")
        else:
            drawn.add_column(header, overflow="fold")
    return drawn


def cells(*values: Any) -> list:
    """Cells as rich Text: never read as markup, and with control characters escaped."""
    from rich.text import Text
    return [Text(printable(str(value))) for value in values]


def show(drawn) -> None:
    """Print the table to stdout: fitted to the terminal, or whole when piped."""
    terminal = sys.stdout.isatty()
    width = shutil.get_terminal_size().columns if terminal else None
    sys.stdout.write(rendered(drawn, terminal_width=width, colour=terminal))
    sys.stdout.flush()


def rendered(drawn, terminal_width: int | None, colour: bool = False) -> str:
    """The table as text, `terminal_width` columns wide at most unless an id needs more (None: piped)."""
    from rich.console import Console
    from rich.measure import Measurement
    probe = Console(width=PIPED, file=io.StringIO())
    need = Measurement.get(probe, probe.options, drawn)
    # rich's minimum keeps each id whole (a no-wrap cell measures its full width); below it, rich's
    # last resort would cut every column, ids too
    width = need.maximum if terminal_width is None else max(terminal_width, need.minimum)
    out = io.StringIO()
    Console(width=width, file=out, highlight=False, force_terminal=colour, no_color=not colour or None,
            legacy_windows=False).print(drawn)
    return out.getvalue()


def text_or_null(value: Any) -> str:
    return "null" if value is None else printable(str(value))
