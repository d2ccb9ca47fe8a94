"""Put audit events on Zenoh, where the ingest subscribes to ``gaps/**``.

Every event goes on the key ``store.key_for(event)`` and nowhere else: the ingest refuses an event whose key
disagrees with its body, so building keys any other way would only manufacture quarantine entries.

Each key gets a Zenoh advanced publisher (store.audit_publisher_options: sequence numbers, so that a
sample lost on a live link is recorded); the publisher as a whole keeps ONE cache of the last ``cache_s``
seconds of every event it published (sim_replay/recent_events.py), answered by one queryable
(sim_replay/cache_queryable.py), so that an ingest restarted within that time, or one that sees a hole
in a source's seqs, fetches what it missed; each source holds a liveliness token
(``gaps/@live/<run>/<src>``) from its first event to its despawn, so that an ingest records when it
stopped publishing (or its process died).
"""
from __future__ import annotations

import logging
import os
from collections.abc import Iterable, Sequence
from types import TracebackType

import zenoh
from zenoh import ext

from store import canonical_json
from store.keys import Signer
from store.wire import (CACHE_S, SYNC_KEY, audit_publisher_options, key_for, live_key, INSECURE_FLAG, WireConfigError,
                        check_producer, exposure, matched_within, session_config, zenoh_message)

from .cache_queryable import CacheQueryable
from .recent_events import MAX_BYTES, MAX_EVENTS, Published, RecentEvents

__all__ = ["EventPublisher", "zenoh_config"]

DESPAWN = "entity.despawn"  # a source's last event: its publishers are released after it
SYNC_TIMEOUT_S = 600.0  # how long close() waits for the ingests to confirm what is on the way
SYNC_MATCH_S = 1.0      # ... and, before asking, for an ingest's sync queryable to be known here
PUT_RUN = 1024          # publish_all encodes up to this many events, then puts them back to back
log = logging.getLogger("gaps.producer")
_Prepared = tuple[ext.AdvancedPublisher, str, dict, bytes]   # publisher, key, event, canonical bytes


def zenoh_config(
    *, listen: Sequence[str] = (), connect: Sequence[str] = (), mode: str | None = "peer",
    config_file: str | os.PathLike | None = None,
) -> zenoh.Config:
    """A producer's session config: the wire contract's (store.session_config), which reaches exactly
    the endpoints named, so that runs and tests never find strangers; with ``config_file`` (an
    operator's Zenoh config: TLS, a certificate, user/password), that file with the endpoints
    given written over it, and its mode unless ``mode`` is given."""
    return session_config(listen=listen, connect=connect, mode=mode, config_file=config_file)


def _open(config: zenoh.Config) -> zenoh.Session:
    """A session, or a WireConfigError saying why Zenoh would not open one (exit 2, as serve's):
    in client mode no router answered, or a TLS handshake was refused (no certificate, another
    authority's)."""
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        raise WireConfigError(f"cannot open Zenoh: {zenoh_message(exc)}") from None


def _source_of(key: str) -> str:
    """gaps/<run>/<src> of a key gaps/<run>/<src>/<kind> (a run and a kind have no slash)."""
    return key.rsplit("/", 1)[0]


def _run_and_src(source: str) -> tuple[str, str]:
    """(run, src) of gaps/<run>/<src>."""
    _, run, src = source.split("/", 2)
    return run, src


class EventPublisher:
    """Publishes events as canonical JSON, RELIABLE and BLOCK, because an audit log may not lose data silently.

    Publishers are declared once per key and kept until their source's despawn, so a long run pays the
    declaration cost per source and kind, not per event; the cache is one for all of them. Events are
    not validated here; the ingest does that and quarantines what it refuses.
    Use it from one thread at a time (per-source order is only meaningful from a single producer anyway).
    """

    def __init__(
        self, session: zenoh.Session | None = None, *, config: zenoh.Config | None = None,
        cache_s: float = CACHE_S, cache_events: int = MAX_EVENTS, cache_bytes: int = MAX_BYTES,
        signer: Signer | None = None, events_signed: bool = False, insecure: bool = False,
    ) -> None:
        """Use ``session`` if given (the caller keeps ownership), else open one from ``config``.
        A config that reaches beyond loopback with no Zenoh authentication is refused (a
        WireConfigError, store/reachability.py's check_producer) unless ``insecure``, which is logged
        (``gaps.producer``, a warning); ``events_signed`` says the caller signs the events it
        puts, as a ``signer`` does.
        The cache holds what was published in the last ``cache_s`` seconds, at most ``cache_events``
        events and ``cache_bytes`` bytes of them (the oldest go first). With ``signer``
        (store.Signer), each event is published with its source's signature."""
        if session is not None and config is not None:
            raise ValueError("give either a session or a config, not both")
        if session is None and config is None:
            config = zenoh_config()
        self.exposure = exposure(config) if config is not None else None
        self.insecure_because = ([] if self.exposure is None else
                                 check_producer(self.exposure, signed=signer is not None or events_signed,
                                                insecure=insecure))
        if self.insecure_because and self.exposure is not None:   # (only an exposure has reasons)
            log.warning("%s: this producer can be reached beyond loopback (%s), and %s", INSECURE_FLAG,
                        "; ".join(self.exposure.reachable), "; and ".join(self.insecure_because))
        self._signer = signer
        self._recent = RecentEvents(cache_s, max_events=cache_events, max_bytes=cache_bytes)
        self._owns_session = session is None
        if session is None:
            assert config is not None       # given, or the default made above
            session = _open(config)
        self._session = session
        try:
            self._cache = CacheQueryable(self._session, self._recent)
        except BaseException:
            if self._owns_session:
                self._session.close()
            raise
        self._publishers: dict[str, ext.AdvancedPublisher] = {}
        self._keys_of: dict[str, list[str]] = {}   # gaps/<run>/<src> -> its keys with a publisher
        self._tokens: dict[str, zenoh.LivelinessToken] = {}   # gaps/<run>/<src> -> its liveliness token
        self._published = False
        self._closed = False
        self.confirmed_by: int | None = None   # ingests that confirmed receipt at close (None: not closed)

    @property
    def session(self) -> zenoh.Session:
        """The underlying session, for callers that also need to subscribe or query on it."""
        return self._session

    @property
    def keys(self) -> tuple[str, ...]:
        """The keys of the living sources' publishers (a despawned source's are undeclared at once;
        what it published stays in the cache)."""
        return tuple(self._publishers)

    @property
    def cache(self) -> RecentEvents:
        """The events kept for ingests that missed them (len, nbytes, index; only the publisher's
        thread may add to it, as a test does to stand for samples the wire lost)."""
        return self._recent

    @property
    def cache_id(self) -> str:
        """The cache's id on the wire (its token is ``gaps/@cache/<id>``)."""
        return self._cache.cache_id

    @property
    def live_sources(self) -> tuple[str, ...]:
        """The sources (gaps/<run>/<src>) holding a liveliness token: spoken and not despawned."""
        return tuple(self._tokens)

    def publish(self, event: dict) -> None:
        """Put one event on its key; blocks while Zenoh's queue is full rather than dropping it.

        A source's entity.despawn is its last word: its liveliness token and its publishers go at
        once (what it published stays in the cache for ``cache_s``): a run that lets thousands of
        road users come and go keeps only the living ones' publishers."""
        self._put_run([self._prepared(event)])

    def publish_all(self, events: Iterable[dict], payloads: Sequence[bytes] | None = None,
                    keys: Sequence[str] | None = None) -> int:
        """Publish events in order (per-source order is what the ingest checks); returns how many.

        They go out in runs of up to PUT_RUN whose puts follow one another with nothing between
        them (each run's events encoded first): a put that finds Zenoh's sending thread idle wakes
        it, and it sends that one sample on its own; puts back to back find it busy and go out
        together. Measured on one core: a put with a microsecond or more of Python before it cost
        14-28 us of wall time and 7-18 us of Zenoh's threads' CPU, against 5 us and under 1 us back
        to back. A run ends after a despawn, whose source's publishers go before the next run's
        events find theirs. A producer with a tick's events at hand (the simulation) hands them
        over together; nothing is held back once this returns.

        ``payloads``, if given, are the events' canonical bytes as already written (a replay's
        stored text: the bytes their hashes cover), put as they are instead of encoding each
        event again; one per event, and only without a signer (a signature changes the bytes).
        ``keys``, with payloads, are the events' keys (key_for's) where the caller keeps them."""
        if payloads is not None and self._signer is not None:
            raise ValueError("a signing publisher encodes each event itself: give no payloads")
        if payloads is not None and keys is not None:
            return self._publish_written(events, payloads, keys)
        count = 0
        run: list[_Prepared] = []
        add = run.append
        prepared, publishers, publisher_for = self._prepared, self._publishers, self._publisher_for
        for event in events:
            if payloads is None:
                add(prepared(event))
            else:                              # _as_written, inline: a thousand a tick
                key = key_for(event) if keys is None else keys[count]
                publisher = publishers.get(key)
                add((publisher_for(key) if publisher is None else publisher, key, event, payloads[count]))
            count += 1
            if len(run) >= PUT_RUN or event["kind"] == DESPAWN:
                self._put_run(run)
                run = []
                add = run.append
        if run:
            self._put_run(run)
        return count

    def _publish_written(self, events: Iterable[dict], payloads: Sequence[bytes], keys: Sequence[str]) -> int:
        """publish_all of events whose bytes and keys are at hand (a simulation's tick): the same
        runs, cut at PUT_RUN and after each despawn, in one pass over the three that makes each
        event's cache entry (RecentEvents) as it finds its publisher, so that a thousand events
        a tick are not gone over again between the puts and the cache."""
        publishers, publisher_for, put_held = self._publishers, self._publisher_for, self._put_held
        found: list[ext.AdvancedPublisher] = []
        held: list[Published] = []
        find, hold = found.append, held.append
        for event, key, payload in zip(events, keys, payloads, strict=True):
            publisher = publishers.get(key)
            find(publisher_for(key) if publisher is None else publisher)
            hold((event["run"], event["src"], event["seq"], key, payload))
            despawn = event["kind"] == DESPAWN
            if despawn or len(found) >= PUT_RUN:
                put_held(found, held, despawn)
                found, held = [], []
                find, hold = found.append, held.append
        if found:
            put_held(found, held, False)
        return len(keys)        # as many as events: zip(strict=True) saw to it

    def _prepared(self, event: dict) -> _Prepared:
        """An event ready to put: its publisher (declared on first use), key, event and exact bytes."""
        key = key_for(event)
        if self._signer is not None:
            event = self._signer.sign(event)
        return self._publisher_for(key), key, event, canonical_json(event)

    def _put_run(self, run: list[_Prepared]) -> None:
        """The run's puts back to back (see publish_all), then each into the cache; a despawn (only
        ever a run's last event) retires its source."""
        self._put_held([publisher for publisher, _, _, _ in run],
                       [(event["run"], event["src"], event["seq"], key, payload) for _, key, event, payload in run],
                       run[-1][2]["kind"] == DESPAWN)

    def _put_held(self, found: list[ext.AdvancedPublisher], held: list[Published], despawn: bool) -> None:
        """_put_run of publishers and their events' cache entries (run, src, seq, key, payload):
        the puts back to back, then the entries into the cache; `despawn`: the last event was
        its source's despawn, which retires the source."""
        for publisher, entry in zip(found, held):
            publisher.put(entry[4])
        self._recent.add_all(held)
        self._published = True
        if despawn:
            self._retire(_source_of(held[-1][3]))

    def wait_until_matched(self, event: dict, timeout: float) -> bool:
        """Whether a subscriber for this event's key appeared within ``timeout`` seconds.

        The cache makes up for an ingest that starts after the first events (it asks it when it
        finds it), but only for ``cache_s``: a producer that starts first may still wait here. A plain
        publisher is declared for the look, since an advanced one does not say whether it matches.
        """
        probe = self._session.declare_publisher(key_for(event))
        try:
            return matched_within(probe, timeout)
        finally:
            probe.undeclare()

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
            matched_within(querier, SYNC_MATCH_S)
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
        for token in self._tokens.values():
            token.undeclare()
        self._cache.close()
        self._publishers.clear()
        self._keys_of.clear()
        self._tokens.clear()
        if self._owns_session:
            self._session.close()

    def _publisher_for(self, key: str) -> ext.AdvancedPublisher:
        """The cached publisher for ``key``, declared with the audit options on first use; the
        source's liveliness token is declared before its first publisher."""
        if self._closed:
            raise RuntimeError("publisher is closed")
        publisher = self._publishers.get(key)
        if publisher is None:
            source = _source_of(key)
            if source not in self._tokens:
                self._tokens[source] = self._session.liveliness().declare_token(live_key(*_run_and_src(source)))
            publisher = ext.declare_advanced_publisher(self._session, key, **audit_publisher_options())
            self._publishers[key] = publisher
            self._keys_of.setdefault(source, []).append(key)
        return publisher

    def _retire(self, source: str) -> None:
        """A despawned source: its token goes now (it has stopped publishing, and says so), and so
        do its publishers (Zenoh's put grows dearer with every publisher the session holds,
        measured: 3.4 us with 1,000, 11 us with 6,000). What was put is already queued on the
        link, and kept in the cache: undeclaring loses none of it. Should the source speak again,
        it gets new ones."""
        token = self._tokens.pop(source, None)
        if token is not None:
            token.undeclare()
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
