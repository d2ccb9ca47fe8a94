"""Forging an entry of any index of a store file in its b-tree pages, as someone holding the file can.

The split view (tests/helpers/split_view.py) hides an index from SQLite by rewriting its
definition; an automatic index (`sqlite_autoindex_*`, made for a UNIQUE or PRIMARY KEY
constraint) has no definition to rewrite. So this changes the bytes of the entry itself: walk
the index's b-tree from its root page (`sqlite_schema.rootpage`, the page size from the file
header), find the cell whose record ends in the row's rowid, and change one of its values in
place, keeping its size (an integer moved by one, a character of a text swapped, a 0 made a 1),
so that the page stays well formed and only that entry disagrees with its row. The format is
SQLite's own (https://www.sqlite.org/fileformat2.html, "B-tree Pages", "Record Format").
"""
from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from pathlib import Path

_INDEX_INTERIOR, _INDEX_LEAF = 2, 10


@dataclass(frozen=True)
class Cell:
    """One index entry: where its record lies in the file, and its values."""

    record_at: int            # file offset of the record (its header size varint)
    length: int               # bytes of the record
    values: tuple             # the record's values, the rowid last


def _varint(data: bytes, at: int) -> tuple[int, int]:
    """SQLite's big-endian varint at `at`: (value, bytes used)."""
    value = 0
    for i in range(8):
        byte = data[at + i]
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, i + 1
    return (value << 8) | data[at + 8], 9


_INT_SIZES = {1: 1, 2: 2, 3: 3, 4: 4, 5: 6, 6: 8}


def _size(serial: int) -> int:
    if serial in _INT_SIZES:
        return _INT_SIZES[serial]
    if serial == 7:
        return 8
    if serial >= 12:
        return (serial - 12) // 2
    return 0


def _fields(data: bytes, at: int) -> list[tuple[int, int, int]]:
    """The record at `at` as (serial type, offset of its header byte, offset of its body)."""
    header_size, used = _varint(data, at)
    head, body, found = at + used, at + header_size, []
    while head < at + header_size:
        serial, used = _varint(data, head)
        found.append((serial, head, body))
        head += used
        body += _size(serial)
    return found


def _value(data: bytes, serial: int, at: int) -> object:
    if serial in _INT_SIZES:
        return int.from_bytes(data[at:at + _INT_SIZES[serial]], "big", signed=True)
    if serial in (8, 9):
        return serial - 8
    if serial >= 13 and serial % 2:
        return data[at:at + _size(serial)].decode("utf-8", "replace")
    if serial >= 12:
        return data[at:at + _size(serial)]
    return None


def _page_size(data: bytes) -> tuple[int, int]:
    size = int.from_bytes(data[16:18], "big")
    return (65536 if size == 1 else size), data[20]


def cells(path: Path, index: str) -> list[Cell]:
    """Every entry of the index whose record lies whole in its page (none spills to overflow
    pages in a store's indexes: their keys are short), in b-tree order."""
    conn = sqlite3.connect(path)
    try:
        (root,) = conn.execute("SELECT rootpage FROM sqlite_schema WHERE type = 'index' AND name = ?",
                               (index,)).fetchone()
    finally:
        conn.close()
    data = path.read_bytes()
    page_size, reserved = _page_size(data)
    usable = page_size - reserved
    local_max = (usable - 12) * 64 // 255 - 23
    found: list[Cell] = []
    _walk(data, root, page_size, local_max, found)
    return found


def _walk(data: bytes, page: int, page_size: int, local_max: int, found: list[Cell]) -> None:
    start = (page - 1) * page_size
    header = start + (100 if page == 1 else 0)
    kind = data[header]
    if kind not in (_INDEX_INTERIOR, _INDEX_LEAF):
        raise ValueError(f"page {page} is not an index b-tree page (type {kind})")
    interior = kind == _INDEX_INTERIOR
    count = int.from_bytes(data[header + 3:header + 5], "big")
    pointers = header + (12 if interior else 8)
    for i in range(count):
        cell = start + int.from_bytes(data[pointers + 2 * i:pointers + 2 * i + 2], "big")
        if interior:
            _walk(data, int.from_bytes(data[cell:cell + 4], "big"), page_size, local_max, found)
            cell += 4
        length, used = _varint(data, cell)
        if length <= local_max:
            record = cell + used
            values = tuple(_value(data, serial, body) for serial, _, body in _fields(data, record))
            found.append(Cell(record, length, values))
    if interior:
        _walk(data, int.from_bytes(data[header + 8:header + 12], "big"), page_size, local_max, found)


def forge_entry(path: Path, index: str, rowid: int, position: int) -> bool:
    """Change value `position` of the index's entry for the row `rowid` in the file's bytes, its
    size kept; False if the index holds no whole entry for that row or the value cannot be changed
    in place (a NULL, an empty text)."""
    wal = Path(f"{path}-wal")
    if wal.exists() and wal.stat().st_size:
        raise ValueError(f"{path} has pages in its write-ahead log: close every connection to it first")
    entry = next((c for c in cells(path, index) if c.values and c.values[-1] == rowid), None)
    if entry is None:
        return False
    data = bytearray(path.read_bytes())
    serial, head, body = _fields(bytes(data), entry.record_at)[position]
    if serial in (8, 9):
        data[head] = 17 - serial                      # 0 <-> 1: the header byte, the record's size kept
    elif serial in _INT_SIZES or serial == 7:
        data[body + _size(serial) - 1] ^= 0x01          # the lowest bit: an integer moved by one
    elif serial >= 12 and _size(serial) > 0:
        at = body + _size(serial) - 1
        if data[at] >= 0x80:                             # keep the text valid UTF-8: change an ASCII character only
            return False
        data[at] = ord("x") if data[at] != ord("x") else ord("y")
    else:
        return False
    path.write_bytes(bytes(data))
    return True
