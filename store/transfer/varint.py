"""Reading a protobuf-style varint (7 bits a byte, low first), as the chain-order attachment
(chain_order.py) writes them."""
from __future__ import annotations


def read_varint(data: bytes, pos: int) -> tuple[int, int]:
    """The value at pos and the position after it; ValueError when the data ends inside it."""
    value = shift = 0
    while True:
        if pos >= len(data):
            raise ValueError("a varint runs past the end of the data")
        byte = data[pos]
        pos += 1
        value |= (byte & 0x7F) << shift
        if not byte & 0x80:
            return value, pos
        shift += 7
