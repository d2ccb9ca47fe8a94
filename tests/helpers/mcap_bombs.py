"""Hostile MCAP chunks for the tests: zstd and lz4 frames that decompress to far more than their
size, with an honest or a lying declared size, spliced between the chunks of a good export.

The zstd frames are written by hand as runs of RLE blocks (4 bytes each for 128 KiB of one byte
value), so a gigabyte costs 32 KB of file and no time to build.
"""

from __future__ import annotations

import struct
from pathlib import Path

MAGIC_LEN = 8
_RLE_BLOCK = 128 << 10


def zstd_rle(size: int, declared: int | None = None, byte: int = 0) -> bytes:
    """A zstd frame producing `size` copies of `byte`; its header states `declared` as the
    content size, or none."""
    if declared is None:
        head = b"\x00\x50"  # no content size; 1 MiB window
    else:
        head = b"\xc0\x50" + struct.pack("<Q", declared)  # 8-byte content size; 1 MiB window
    blocks = bytearray()
    left = size
    while left > 0:
        n = min(left, _RLE_BLOCK)
        left -= n
        header = (1 if left == 0 else 0) | (1 << 1) | (n << 3)
        blocks += header.to_bytes(3, "little") + bytes([byte])
    return b"\x28\xb5\x2f\xfd" + head + bytes(blocks)


def chunk_record(compression: str, data: bytes, declared: int, crc: int = 0) -> bytes:
    """A whole Chunk record (opcode, length, body) around already compressed `data`."""
    name = compression.encode()
    body = (struct.pack("<QQQI", 0, 0, declared, crc) + struct.pack("<I", len(name)) + name
            + struct.pack("<Q", len(data)) + data)
    return struct.pack("<BQ", 0x06, len(body)) + body


def top_level_records(data: bytes) -> list[tuple[int, int, int]]:
    """(offset, opcode, end) of each record after the magic, framed by their lengths."""
    out, at = [], MAGIC_LEN
    while at + 9 <= len(data):
        opcode, length = struct.unpack_from("<BQ", data, at)
        out.append((at, opcode, at + 9 + length))
        at += 9 + length
    return out


def splice_after_first_chunk(good: bytes, inserted: list[bytes]) -> tuple[bytes, list[int]]:
    """The good file with `inserted` records placed right after its first chunk; returns the new
    bytes and the offset each inserted record starts at."""
    first_chunk_end = next(end for at, opcode, end in top_level_records(good) if opcode == 0x06)
    out, offsets = bytearray(good[:first_chunk_end]), []
    for record in inserted:
        offsets.append(len(out))
        out += record
    return bytes(out + good[first_chunk_end:]), offsets


def write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path
