"""Reading an MCAP file's records front to back, knowing where each one starts and where the file
stops being readable.

A recording cut short (a full disk, a killed recorder, a partial copy) has no footer and may end
in the middle of a record. The official readers either need the summary at the end or read until
an exception; here each record is framed by hand (opcode, length, then exactly that many bytes,
never more than the file still holds), parsed with the mcap package's record classes, and the
first record that is not all there ends the reading with a Cut that says where and why. A chunk
that is all there but cannot be decoded (CRC mismatch, corrupt compression, a decompression bomb:
mcap_chunks.py) is listed as damaged and reading goes on past it: its length framed it, so the
records after it are still sound.
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, field
from io import BytesIO
from typing import Any, BinaryIO, Callable, Iterator, NamedTuple

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import Attachment, Channel, Chunk, DataEnd, Footer, Header, McapRecord, Message, Metadata, Schema

from .errors import TransferError
from .mcap_chunks import MAX_CHUNK_BYTES, Budget, ChunkRefused, chunk_bytes, chunk_records  # noqa: F401

MAGIC = b"\x89MCAP0\r\n"
_FRAME = struct.Struct("<BQ")  # opcode, record length


def _attachment(stream: ReadDataStream, length: int) -> Attachment:
    """An Attachment, its CRC checked (the mcap package skips it): the chain order travels in one."""
    body = stream.read(length)
    record = Attachment.read(ReadDataStream(BytesIO(body)))
    (crc,) = struct.unpack("<I", body[-4:])
    if crc and crc != zlib.crc32(body[:-4]):
        raise ValueError(f"CRC mismatch in attachment {record.name!r}")
    return record


# Only what an import needs is parsed; every other record (indexes, statistics) is framed and
# passed over, so a damaged index never stops an import of intact messages.
_PARSERS: dict[int, Callable[[ReadDataStream, int], McapRecord]] = {
    Opcode.ATTACHMENT: _attachment,
    Opcode.HEADER: lambda s, n: Header.read(s),
    Opcode.SCHEMA: lambda s, n: Schema.read(s),
    Opcode.CHANNEL: lambda s, n: Channel.read(s),
    Opcode.MESSAGE: lambda s, n: Message.read(s, n),
    Opcode.CHUNK: lambda s, n: Chunk.read(s),
    Opcode.METADATA: lambda s, n: Metadata.read(s),
    Opcode.DATA_END: lambda s, n: DataEnd.read(s),
    Opcode.FOOTER: lambda s, n: Footer.read(s),
}


def opcode_name(opcode: int) -> str:
    try:
        return Opcode(opcode).name.title().replace("_", "")
    except ValueError:
        return f"unknown record (opcode 0x{opcode:02x})"


@dataclass(frozen=True)
class Cut:
    """Where the readable part of a file ends. `offset` is the first byte not read as a whole
    record; `record` and `declared` describe the record that starts there, when its frame was
    readable; `data_complete` says whether the data section ended (DataEnd) before the cut, in
    which case every message was read and only the summary and footer are missing."""

    offset: int
    file_size: int
    reason: str
    record: str | None = None
    declared: int | None = None
    data_complete: bool = False

    @property
    def unreadable_bytes(self) -> int:
        return self.file_size - self.offset


@dataclass(frozen=True)
class Damage:
    """A record that could not be read and was read past: where it starts, what it was, why."""

    offset: int
    record: str
    reason: str

    def to_json(self) -> dict[str, Any]:
        return {"offset": self.offset, "record": self.record, "reason": self.reason}


class Located(NamedTuple):
    offset: int  # where the record starts; for a record inside a chunk, where the chunk starts
    in_chunk: bool
    record: McapRecord


@dataclass
class RecordReader:
    """Reads a stream once, in order, without seeking; `size` is the file's size in bytes."""

    stream: BinaryIO
    size: int
    name: str
    position: int = 0
    cut: Cut | None = None
    damaged: list[Damage] = field(default_factory=list)
    data_ended: bool = False
    budget: Budget = field(init=False)

    def __post_init__(self) -> None:
        self.budget = Budget.for_file(self.size)

    def records(self) -> Iterator[Located]:
        """Every readable record; when it stops early, `cut` says why."""
        self._read_magic()
        while True:
            framed = self._frame()
            if framed is None:
                return
            offset, opcode, body = framed
            record = self._parse(offset, opcode, body)
            if isinstance(record, Chunk):
                yield from self._unchunk(offset, record)
            elif record is not None:
                yield Located(offset, False, record)
            if isinstance(record, DataEnd):
                self.data_ended = True
            if isinstance(record, Footer):
                self._read_closing_magic()
                return

    def _read_magic(self) -> None:
        start = self.stream.read(len(MAGIC))
        if start != MAGIC:
            if not start:
                what = "the file is empty"
            elif MAGIC.startswith(start):
                what = f"it ends after {len(start)} bytes, inside the 8 MCAP magic bytes: nothing to import"
            else:
                what = "it does not start with the 8 MCAP magic bytes"
            raise TransferError(f"{self.name}: not an MCAP file: {what}")
        self.position = len(MAGIC)

    def _frame(self) -> tuple[int, int, bytes] | None:
        """The next record's (offset, opcode, body), or None at a cut."""
        offset = self.position
        head = self.stream.read(_FRAME.size)
        if not head:
            self._stop(offset, "the file ends after a complete record, without a footer")
            return None
        if len(head) < _FRAME.size:
            self._stop(offset, f"the file ends inside the frame of a record ({len(head)} of 9 bytes)")
            return None
        opcode, length = _FRAME.unpack(head)
        remaining = self.size - offset - _FRAME.size
        if length > remaining:
            name = opcode_name(opcode)
            self._stop(offset, f"a {name} record of {length} bytes starts here, but only "
                               f"{max(remaining, 0)} bytes of it are in the file", name, length)
            return None
        body = self.stream.read(length)
        if len(body) < length:  # the file shrank while we read it
            self._stop(offset, f"the file ended {len(body)} bytes into a {length}-byte record",
                       opcode_name(opcode), length)
            return None
        self.position = offset + _FRAME.size + length
        return offset, opcode, body

    def _stop(self, offset: int, reason: str, record: str | None = None, declared: int | None = None) -> None:
        self.cut = Cut(offset, self.size, reason, record, declared, self.data_ended)

    def _parse(self, offset: int, opcode: int, body: bytes) -> McapRecord | None:
        parser = _PARSERS.get(opcode)
        if parser is None:
            return None
        try:
            return parser(ReadDataStream(BytesIO(body)), len(body))
        except Exception as exc:  # hostile bytes reach third-party parsing: any failure means "damaged"
            self._damage(offset, opcode_name(opcode), f"cannot be parsed: {_describe(exc)}")
            return None

    def _unchunk(self, offset: int, chunk: Chunk) -> Iterator[Located]:
        """The chunk's records, decompressed within the file's budget (mcap_chunks.py); a chunk
        refused is listed as damaged, and reading goes on after it. Each Located is built as a
        plain tuple (all fields given), not through the NamedTuple's Python __new__: a chunk
        gives thousands."""
        new = tuple.__new__
        try:
            for record in chunk_records(chunk_bytes(chunk, self.budget)):
                yield new(Located, (offset, True, record))
        except ChunkRefused as exc:
            self._damage(offset, "Chunk", f"cannot be decoded ({chunk.compression or 'uncompressed'}, "
                                          f"log times {chunk.message_start_time}..{chunk.message_end_time}): {exc}")

    def _damage(self, offset: int, record: str, reason: str) -> None:
        self.damaged.append(Damage(offset, record, reason))

    def _read_closing_magic(self) -> None:
        end = self.stream.read(len(MAGIC))
        if end != MAGIC:
            self._stop(self.position, "the footer is not followed by the closing MCAP magic bytes")
        else:
            self.position += len(MAGIC)


def _describe(exc: Exception) -> str:
    text = str(exc) or "no detail"
    return f"{type(exc).__name__}: {text[:200]}"
