"""Reading a protobuf FileDescriptorSet: the message and enum definitions it holds, by full name.

Foxglove's SDK publishes its well-known schemas (foxglove.SceneUpdate, foxglove.Log, ...) as the
protobuf descriptors it writes into MCAP files; foxglove_schemas.py turns those into JSON Schemas.
Only the few fields of descriptor.proto that say what a message looks like are read (file package,
message and enum names, field names, numbers, labels, types and type names); everything else
(options, source info, services) is passed over. The wire format is small enough to read here
rather than add the protobuf runtime as a dependency for it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator

from .varint import read_varint

_VARINT, _I64, _LEN, _I32 = 0, 1, 2, 5
REPEATED = 3  # FieldDescriptorProto.Label


@dataclass(frozen=True)
class FieldDef:
    name: str
    number: int
    type: int  # FieldDescriptorProto.Type: 1 double, 8 bool, 9 string, 11 message, 12 bytes, 14 enum, ...
    type_name: str  # ".foxglove.Pose" for a message or enum field, "" otherwise
    repeated: bool


@dataclass(frozen=True)
class MessageDef:
    name: str  # full name, "foxglove.SceneUpdate"
    fields: tuple[FieldDef, ...]


@dataclass(frozen=True)
class EnumDef:
    name: str  # full name, "foxglove.LogLevel"
    values: tuple[tuple[str, int], ...]  # (name, number), in declaration order


@dataclass
class Definitions:
    messages: dict[str, MessageDef] = field(default_factory=dict)
    enums: dict[str, EnumDef] = field(default_factory=dict)


class DescriptorError(ValueError):
    """The bytes are not a FileDescriptorSet this reader understands."""


def _varint(data: bytes, pos: int) -> tuple[int, int]:
    try:
        return read_varint(data, pos)
    except ValueError as exc:
        raise DescriptorError(str(exc)) from None


def _fields(data: bytes) -> Iterator[tuple[int, int | bytes]]:
    """(field number, value) of each field of one message: an int, or the bytes of a LEN field."""
    pos = 0
    while pos < len(data):
        key, pos = _varint(data, pos)
        number, wire = key >> 3, key & 7
        if wire == _VARINT:
            value, pos = _varint(data, pos)
            yield number, value
        elif wire == _LEN:
            length, pos = _varint(data, pos)
            if pos + length > len(data):
                raise DescriptorError("a length-delimited field runs past the end of the data")
            yield number, data[pos:pos + length]
            pos += length
        elif wire in (_I64, _I32):
            pos += 8 if wire == _I64 else 4
        else:
            raise DescriptorError(f"unsupported wire type {wire}")


def _text(value: int | bytes) -> str:
    return value.decode("utf-8") if isinstance(value, bytes) else ""


def _field(data: bytes) -> FieldDef:
    name, number, label, kind, type_name = "", 0, 0, 0, ""
    for tag, value in _fields(data):
        if tag == 1:
            name = _text(value)
        elif tag == 3 and isinstance(value, int):
            number = value
        elif tag == 4 and isinstance(value, int):
            label = value
        elif tag == 5 and isinstance(value, int):
            kind = value
        elif tag == 6:
            type_name = _text(value)
    return FieldDef(name, number, kind, type_name, label == REPEATED)


def _enum_value(data: bytes) -> tuple[str, int]:
    name, number = "", 0
    for tag, value in _fields(data):
        if tag == 1:
            name = _text(value)
        elif tag == 2 and isinstance(value, int):
            number = value - (1 << 64) if value >= 1 << 63 else value  # int32, sign-extended on the wire
    return name, number


def _enum(data: bytes, scope: str, out: Definitions) -> None:
    name, values = "", []
    for tag, value in _fields(data):
        if tag == 1:
            name = _text(value)
        elif tag == 2 and isinstance(value, bytes):
            values.append(_enum_value(value))
    full = f"{scope}.{name}" if scope else name
    out.enums[full] = EnumDef(full, tuple(values))


def _message(data: bytes, scope: str, out: Definitions) -> None:
    name, fields, nested, enums = "", [], [], []
    for tag, value in _fields(data):
        if not isinstance(value, bytes):
            continue
        if tag == 1:
            name = value.decode("utf-8")
        elif tag == 2:
            fields.append(_field(value))
        elif tag == 3:
            nested.append(value)
        elif tag == 4:
            enums.append(value)
    full = f"{scope}.{name}" if scope else name
    out.messages[full] = MessageDef(full, tuple(fields))
    for item in nested:
        _message(item, full, out)
    for item in enums:
        _enum(item, full, out)


def read_descriptor_set(data: bytes) -> Definitions:
    """Every message and enum of a serialized FileDescriptorSet, by full name (no leading dot)."""
    out = Definitions()
    for tag, file_bytes in _fields(bytes(data)):
        if tag != 1 or not isinstance(file_bytes, bytes):
            continue
        parts = list(_fields(file_bytes))
        package = next((_text(v) for t, v in parts if t == 2), "")
        for tag, value in parts:
            if tag == 4 and isinstance(value, bytes):
                _message(value, package, out)
            elif tag == 5 and isinstance(value, bytes):
                _enum(value, package, out)
    return out
