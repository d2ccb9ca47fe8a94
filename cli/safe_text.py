"""Showing hostile text on a terminal: whatever a producer sent is shown, never obeyed.

Quarantined bytes, origins and reasons may hold terminal escape sequences, rich markup or invalid
UTF-8; they are written with every non-printable character escaped, so an investigator sees
exactly what arrived and the terminal is not told to do anything.
"""
from __future__ import annotations

_SURROGATES = range(0xDC80, 0xDD00)  # where surrogateescape puts bytes that are not UTF-8


def printable(text: str) -> str:
    """Text with backslashes doubled and every non-printable character as an escape."""
    return "".join(_escape(ch) for ch in text)


def preview(raw: bytes, limit: int = 60) -> str:
    """The first `limit` bytes, decoded as UTF-8 where they are, escaped; … if there is more."""
    text = printable(raw[:limit].decode("utf-8", "surrogateescape"))
    return text + "…" if len(raw) > limit else text


def _escape(ch: str) -> str:
    if ch == "\\":
        return "\\\\"
    if ch.isprintable():
        return ch
    code = ord(ch)
    if code in _SURROGATES:
        return f"\\x{code - 0xDC00:02x}"
    return ch.encode("unicode_escape").decode("ascii")
