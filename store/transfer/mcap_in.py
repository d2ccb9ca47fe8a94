"""MCAP in: every JSON message whose payload is an event envelope goes to the store.

Accepted: our own exports, and JSON channels written by other tools, with a jsonschema schema or
none (schema id 0). Each message is judged by the store like any other input and quarantined
with its bytes and origin `FILE:channel TOPIC:message N (log_time T, where)` if refused; on a
topic that is a gaps key expression, the event must also be the one that key names. Messages the
store has no use for are counted as skipped, per channel, with the reason: the derived Foxglove
channels of our own exports (they are rebuilt from the events on export) and channels in an
encoding other than JSON. A file cut short imports everything before the cut (see mcap_records).

Messages come in log-time order; when the file carries its run's chain order (the
`gaps.chain_order` attachment, chain_order.py), the events go to the store in that order, so that
the run's chain heads are rebuilt. A file without it (older exports, which were written in chain
order, and other tools' files) is imported in file order. Schemas are not checked against the
store's: the store judges every event by its own schemas, whatever the file's say (older exports
carry the exact schemas, newer ones viewer-safe copies).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Iterator, cast

from mcap.records import Attachment, Channel, Message, Metadata, Schema

from ..db import Store
from ..envelope import key_for
from ..intake import Candidate, from_raw
from . import chain_order
from .chain_check import ChainCheck, ChainResult
from .errors import TransferError
from .feed import feed
from .foxglove_channels import DERIVED_MARK
from .mcap_records import Damage, Located, RecordReader
from .outcomes import ImportReport, Truncation

_EVENT_TOPIC_PREFIX = "gaps/"

Progress = Callable[[int], None]


@dataclass
class _Route:
    """What to do with a channel's messages: import them (reason None) or skip them, and why."""

    topic: str
    skip_reason: str | None
    count: int = 0
    keyed: bool = field(init=False)  # a gaps key expression: each event must be the one it names

    def __post_init__(self) -> None:
        self.keyed = self.topic.startswith(_EVENT_TOPIC_PREFIX)


def route(channel: Channel, schema: Schema | None) -> _Route:
    """Decide once per channel whether its messages can be events."""
    if DERIVED_MARK in channel.metadata or (schema is not None and schema.name.startswith("foxglove.")):
        name = schema.name if schema is not None else "visualisation"
        return _Route(channel.topic, f"derived {name} channel: rebuilt from the events on export")
    if channel.message_encoding.lower() != "json":
        return _Route(channel.topic, f"message encoding {channel.message_encoding or '(none)'!r} is not json")
    return _Route(channel.topic, None)


class _Messages:
    """Turns the records of one file into store candidates, keeping the file's channels and
    schemas, the skip counts, and the chain check as it goes."""

    def __init__(self, reader: RecordReader, report: ImportReport, chains: ChainCheck) -> None:
        self.reader, self.report, self.chains = reader, report, chains
        self.schemas: dict[int, Schema] = {}
        self.routes: dict[int, _Route] = {}
        self.messages = 0  # event messages read (offered to the store)
        self.reorder = chain_order.Reorder()

    def candidates(self) -> Iterator[Candidate]:
        push, in_chain_order = self.reorder.push, self._in_chain_order
        for located in self.reader.records():
            record = located.record
            if isinstance(record, Message):
                candidate = self._message(located, record)
                if candidate is not None:
                    yield from in_chain_order(push(candidate))
            elif isinstance(record, Schema):
                self.schemas.setdefault(record.id, record)
            elif isinstance(record, Channel):
                self.routes.setdefault(record.id, route(record, self.schemas.get(record.schema_id)))
            elif isinstance(record, Metadata):
                self.chains.metadata(record.name, record.metadata)
            elif isinstance(record, Attachment) and record.name == chain_order.ATTACHMENT:
                self._chain_order(located, record)
        yield from self._in_chain_order(self.reorder.finish())

    def _in_chain_order(self, released: list[Candidate]) -> list[Candidate]:
        """The candidates the reordering lets go, each extending the file's chain (a list, not a
        generator: one is made for every message read, and the chain check reads no store)."""
        observe = self.chains.observe
        for candidate in released:
            if candidate.event is not None and candidate.reason is None:
                observe(candidate.event, cast(bytes, candidate.canonical))  # accepted: it has its bytes
        return released

    def _chain_order(self, located: Located, record: Attachment) -> None:
        try:
            self.reorder.expect(chain_order.decode(record.data))
        except ValueError as exc:
            self.reader.damaged.append(Damage(located.offset, f"Attachment {record.name}",
                                              f"{exc}; the events are imported in file order"))

    def _message(self, located: Located, message: Message) -> Candidate | None:
        offset, in_chunk, _ = located
        channel = self.routes.get(message.channel_id)
        if channel is None:
            self.messages += 1
            where = f"{'chunk at' if in_chunk else 'record at'} byte {offset}"
            origin = f"{self.reader.name}:channel id {message.channel_id}:message (log_time {message.log_time}, {where})"
            reason = f"message on channel id {message.channel_id}, which no Channel record before it defines"
            return Candidate(origin, message.data, reason=reason)
        channel.count += 1
        if channel.skip_reason is not None:
            self.report.skip(f"channel {channel.topic}", channel.skip_reason)
            return None
        self.messages += 1
        origin = (f"{self.reader.name}:channel {channel.topic}:message {channel.count} (log_time {message.log_time}, "
                  f"{'chunk at' if in_chunk else 'record at'} byte {offset})")
        candidate = from_raw(message.data, origin)
        if candidate.event is None:
            return candidate
        if channel.keyed and key_for(candidate.event) != channel.topic:
            reason = f"channel topic {channel.topic} does not match the event's own key {key_for(candidate.event)}"
            return Candidate(origin, message.data, reason=reason)
        return candidate


def import_mcap(store: Store, path: Path, report: ImportReport, progress: Progress | None = None) -> None:
    """Import every event message of an MCAP file; say what was skipped and where a cut file ends."""
    try:
        stream = open(path, "rb")
    except OSError as exc:
        raise TransferError(f"cannot read {path}: {exc.strerror or exc}") from None
    with stream:
        reader = RecordReader(stream, os.fstat(stream.fileno()).st_size, str(path))
        chains = ChainCheck()
        messages = _Messages(reader, report, chains)
        after = None if progress is None else (lambda: progress(reader.position))
        feed(store, messages.candidates(), report, after_batch=after)
    report.damaged.extend(reader.damaged)
    report.chains.extend(_abandoned(result, messages.reorder) for result in chains.results(store))
    if reader.cut is not None:
        report.truncated = Truncation(reader.cut, messages.messages, report.stored)


def _abandoned(result: ChainResult, reorder: chain_order.Reorder) -> ChainResult:
    """The run's chain check, saying so if its chain order was not followed to the end."""
    if result.run not in reorder.abandoned:
        return result
    return replace(result, chain_order=("not followed to the end: an event it lists is missing from the file, "
                                        f"or more than {reorder.max_held} events came before their turn; "
                                        "the rest of the run was imported in file order"))
