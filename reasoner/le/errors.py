"""Errors and warnings in Logical English documents, located so that a rule author can fix them."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from store import GapsError


@dataclass
class Located:
    """A message about a place in an LE document, with a hint on how to fix it."""

    message: str
    file: str = "<le>"
    line: int = 0
    column: int = 1
    hint: str = ""

    _kind: ClassVar[str] = ""   # what str() says before the message ("warning: ")

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}:{self.column}"
        return f"{where}: {self._kind}{self.message}" + (f" (hint: {self.hint})" if self.hint else "")

    def as_dict(self) -> dict:
        return {"file": self.file, "line": self.line, "column": self.column,
                "message": self.message, "hint": self.hint}


@dataclass(eq=False)
class LEError(Located, GapsError):
    """A problem in an LE document; `str()` gives `file:line:column: message (hint)`."""


@dataclass
class LEWarning(Located):
    """Something that compiles but probably is not what the author meant."""

    _kind: ClassVar[str] = "warning: "
