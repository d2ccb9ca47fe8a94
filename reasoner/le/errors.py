"""Errors and warnings in Logical English documents, located so that a rule author can fix them."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass
class LEError(Exception):
    """A problem in an LE document; `str()` gives `file:line:column: message (hint)`."""

    message: str
    file: str = "<le>"
    line: int = 0
    column: int = 1
    hint: str = ""

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}:{self.column}"
        return f"{where}: {self.message}" + (f" (hint: {self.hint})" if self.hint else "")

    def as_dict(self) -> dict:
        return {"file": self.file, "line": self.line, "column": self.column,
                "message": self.message, "hint": self.hint}


@dataclass
class LEWarning:
    """Something that compiles but probably is not what the author meant."""

    message: str
    file: str = "<le>"
    line: int = 0
    column: int = 1
    hint: str = ""

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}:{self.column}"
        return f"{where}: warning: {self.message}" + (f" (hint: {self.hint})" if self.hint else "")

    def as_dict(self) -> dict:
        return {"file": self.file, "line": self.line, "column": self.column,
                "message": self.message, "hint": self.hint}
