"""A progress bar on stderr for long jobs, so stdout stays clean for text and JSON output."""
from __future__ import annotations

from contextlib import contextmanager
from typing import Callable, Iterator, Optional

Report = Callable[[int, Optional[int]], None]  # (done, total; None: not known yet)


@contextmanager
def stderr_progress(label: str) -> Iterator[Optional[Report]]:
    """Yield a (done, total) callback drawing a rich bar, when stderr is a terminal; else None."""
    from rich.console import Console
    console = Console(stderr=True)
    if not console.is_terminal:
        yield None
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn
    with Progress(TextColumn(label), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                  console=console, transient=True) as bar:
        task = bar.add_task(label, total=None)
        yield lambda done, total: bar.update(task, completed=done, total=total)
