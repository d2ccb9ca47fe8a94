"""Tables on the terminal (rich), with every cell escaped: recorded text is shown, never obeyed."""
from __future__ import annotations

from typing import Any

from cli.safe_text import printable


def table(*headers: str):
    from rich.table import Table
    return Table(*headers)


def cells(*values: Any) -> list:
    """Cells as rich Text: never read as markup, and with control characters escaped."""
    from rich.text import Text
    return [Text(printable(str(value))) for value in values]


def show(drawn) -> None:
    from rich.console import Console
    Console(highlight=False).print(drawn)


def text_or_null(value: Any) -> str:
    return "null" if value is None else printable(str(value))
