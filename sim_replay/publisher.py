"""Put audit events on Zenoh, where the ingest subscribes to ``gaps/**``.

Every event goes on the key ``store.key_for(event)`` and nowhere else: the ingest refuses an event whose key
disagrees with its body, so building keys any other way would only manufacture quarantine entries.
"""
from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from types import TracebackType

import zenoh

from store import SYNC_KEY, Signer, audit_qos, canonical_json, key_for, session_config

__all__ = ["EventPublisher", "zenoh_config"]

DESPAWN = "entity.despawn"  # a source's last event: its publishers are released after it
SYNC_TIMEOUT_S = 600.0  # how long close() waits for the ingests to confirm what is on the way
SYNC_MATCH_S = 1.0      # ... and, before asking, for an ingest's sync queryable to be known here


def zenoh_config(
    *, listen: Sequence[str] = (), connect: Sequence[str] = (), mode: str = "peer"
) -> zenoh.Config:
    """A producer's session config: the wire contract's (store.session_config), which reaches exactly
    the endpoints named, so that runs and tests never find strangers."""
    return session_config(listen=listen, connect=connect, mode=mode)


def _source_of(key: str) -> str:
    """gaps/<run>/<src> of a key gaps/<run>/<src>/<kind> (a run and a kind have no slash)."""
    return key.rsplit("/", 1)[0]


def _matching(publisher: zenoh.Publisher | zenoh.Querier) -> bool:
    """Whether a subscriber (a queryable) matches; zenoh 1.10 returns a MatchingStatus here despite its
    stub saying bool."""
    status = publisher.matching_status
    return bool(getattr(status, "matching", status))


class EventPublisher:
    """Publishes events as canonical JSON, RELIABLE and BLOCK, because an audit log may not lose data silently.

    Publishers are declared once per key and cached, so a long run pays the declaration cost per source and
    kind, not per event. Events are not validated here; the ingest does that and quarantines what it refuses.
    Use it from one thread at a time (per-source order is only meaningful from a single producer anyway).
    """

    def __init__(
        self, session: zenoh.Session | None = None, *, config: zenoh.Config | None = None,
        signer: Signer | None = None,
    ) -> None:
        """Use ``session`` if given (the caller keeps ownership), else open one from ``config``.
        With ``signer`` (store.Signer), each event is published with its source's signature."""
        if session is not None and config is not None:
            raise ValueError("give either a session or a config, not both")
        self._signer = signer
        self._owns_session = session is None
        self._session = session if session is not None else zenoh.open(config or zenoh_config())
        self._publishers: dict[str, zenoh.Publisher] = {}
        self._keys_of: dict[str, list[str]] = {}   # gaps/<run>/<src> -> its keys with a publisher
        self._published = False
        self._closed = False
        self.confirmed_by: int | None = None   # ingests that confirmed receipt at close (None: not closed)

    @property
    def session(self) -> zenoh.Session:
        """The underlying session, for callers that also need to subscribe or query on it."""
        return self._session

    @property
    def keys(self) -> tuple[str, ...]:
        """The keys this session holds a publisher for (what `_release` keeps in bounds)."""
        return tuple(self._publishers)

    def publish(self, event: dict) -> None:
        """Put one event on its key; blocks while Zenoh's queue is full rather than dropping it.

        A source's entity.despawn is its last word, so its publishers are undeclared after it
        (`_release`): a run that lets thousands of road users come and go keeps only the living
        ones' publishers."""
        key = key_for(event)
        if self._signer is not None:
            event = self._signer.sign(event)
        self._publisher_for(key).put(canonical_json(event))
        self._published = True
        if event["kind"] == DESPAWN:
            self._release(_source_of(key))

    def publish_all(self, events: Iterable[dict]) -> int:
        """Publish events in order (per-source order is what the ingest checks); returns how many."""
        count = 0
        for event in events:
            self.publish(event)
            count += 1
        return count

    def wait_until_matched(self, event: dict, timeout: float) -> bool:
        """Whether a subscriber for this event's key appeared within ``timeout`` seconds.

        Pub/sub keeps no history: what is put before the ingest's subscription has reached this session is
        gone, so a producer that starts first should wait here before its first event.
        """
        publisher = self._publisher_for(key_for(event))
        deadline = time.monotonic() + timeout
        while not _matching(publisher):
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.01)
        return True

    def sync(self, timeout: float = SYNC_TIMEOUT_S) -> int:
        """Wait until every ingest has what was published before; returns how many ingests said so
        (0: none answers, e.g. a foreign subscriber, or none within ``timeout``).

        An ingest declares its sync queryable just after its subscriber, and the declarations
        reach this session one by one: a publisher that matched the subscriber a moment ago may
        not know the queryable yet, and a query then finds nobody to ask (seen in a test that
        published two events and closed at once). So the query waits up to SYNC_MATCH_S for a
        queryable to match first."""
        querier = self._session.declare_querier(SYNC_KEY, target=zenoh.QueryTarget.ALL,
                                                consolidation=zenoh.ConsolidationMode.NONE, timeout=timeout)
        try:
            deadline = time.monotonic() + SYNC_MATCH_S
            while not _matching(querier) and time.monotonic() < deadline:
                time.sleep(0.01)
            return sum(1 for reply in querier.get() if reply.ok is not None)
        finally:
            querier.undeclare()

    def close(self) -> None:
        """Undeclare the publishers, and close the session if this object opened it. Safe to call twice.

        Anything published is first confirmed by the ingests (`sync`): a session closed with samples
        still queued drops them (measured: 7,500 of 60,000 to a slow subscriber)."""
        if self._closed:
            return
        if self._published:
            self.confirmed_by = self.sync()
        self._closed = True
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()
        self._keys_of.clear()
        if self._owns_session:
            self._session.close()

    def _publisher_for(self, key: str) -> zenoh.Publisher:
        """The cached publisher for ``key``, declared with the audit QoS on first use."""
        if self._closed:
            raise RuntimeError("publisher is closed")
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._session.declare_publisher(key, **audit_qos())
            self._publishers[key] = publisher
            self._keys_of.setdefault(_source_of(key), []).append(key)
        return publisher

    def _release(self, source: str) -> None:
        """Undeclare a source's publishers. Zenoh's put grows dearer with every publisher the session
        holds (measured: 3.4 us with 1,000, 11 us with 6,000), and a despawned road user never
        publishes again; should a source speak after its despawn, its publisher is declared anew.
        What was put before is already queued on the link: undeclaring loses none of it."""
        for key in self._keys_of.pop(source, ()):
            publisher = self._publishers.pop(key, None)
            if publisher is not None:
                publisher.undeclare()

    def __enter__(self) -> EventPublisher:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
