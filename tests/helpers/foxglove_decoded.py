"""The Foxglove channels of an exported MCAP file as a viewer reads them: decoded by the MCAP
reader's protobuf decoder (mcap-protobuf-support, on Google's protobuf runtime) from the schema the
file carries, never by our own code."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any

from mcap.reader import make_reader
from mcap.records import Schema
from mcap_protobuf.decoder import DecoderFactory


def decoded(path: Path, topic: str) -> list[tuple[int, Any]]:
    """(log time, decoded protobuf message) of every message on `topic`, in log-time order."""
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        return [(message.log_time, proto) for _, _, message, proto in reader.iter_decoded_messages(topics=[topic])]


@lru_cache(maxsize=None)
def decoder(name: str, encoding: str, data: bytes):
    """The function that decodes messages of one schema (the SDK's, or a file's)."""
    decode = DecoderFactory().decoder_for("protobuf", Schema(id=1, name=name, encoding=encoding, data=data))
    assert decode is not None, f"no protobuf decoder for schema {name} in {encoding}"
    return decode


def alive_at(events: list[dict], t: int) -> dict[str, dict]:
    """The road users alive at t, each with its latest state: worked out from the events alone."""
    alive: dict[str, dict] = {}
    for ev in sorted(events, key=lambda e: (e["t"], e["seq"], e["src"])):
        if ev["t"] > t:
            break
        if ev["kind"] == "entity.state":
            alive[ev["src"]] = ev["body"]
        elif ev["kind"] == "entity.despawn":
            alive.pop(ev["src"], None)
    return alive
