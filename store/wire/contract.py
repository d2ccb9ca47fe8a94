"""The wire contract in one module: how every gaps session meets Zenoh (the config builder), what a
producer's publishers promise (the audit QoS), and where events and the sync question go (the key
expressions, `key_for` and `SYNC_KEY`, beside the envelope in store/envelope.py).

Every producer (`gaps sim`, replays, the publisher API) and every ingest (`gaps serve`, the
in-process ingest of `gaps demo`) builds its session here, so the two sides cannot drift apart.
It lives in the store because the store is the room every other room may import (DESIGN's table),
and the keys are the envelope's.

Explicit endpoints only, no scouting, unless an operator's file says otherwise: an audit session
should reach the peers it was pointed at, not whatever answers a multicast probe; ``--listen`` and
``--connect`` map one to one onto the arguments. An operator with a Zenoh config file of their own
(``gaps serve --config zenoh.json5``: TLS, access control, tuned transports) gets exactly that file,
with only the options given on the command line written over it.
"""
from __future__ import annotations

import json
import os
import re
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..envelope import SYNC_KEY, key_for
from ..errors import GapsError

if TYPE_CHECKING:       # imported where used: `gaps --help` and every reader of a store load no Zenoh
    import zenoh

__all__ = ["BLOCK_FOR_US", "CACHE_S", "LIVE_PREFIX", "MODES", "SYNC_KEY", "WireConfigError",
           "audit_publisher_options", "audit_qos", "key_for", "live_key", "live_slice",
           "session_config", "source_of_live_key", "zenoh_message"]

BLOCK_FOR_US = 3_600_000_000
"""How long a put may wait for room before Zenoh gives up the link (microseconds). Zenoh's default is
5 s, after which it closes the link and the puts that follow vanish without an error (measured: an
ingest that paused 8 s lost 50,000 of 60,000 events); an audit producer waits instead. A dead ingest
is still found within the lease (10 s), which closes the link whatever this says."""


class WireConfigError(GapsError, ValueError):
    """An option, a Zenoh config file, an endpoint or a key expression that cannot be used (exit 2).
    A ValueError too, as a bad mode was before this class existed."""


def audit_qos() -> dict[str, Any]:
    """What every event publisher is declared with: JSON, RELIABLE and BLOCK, because an audit log
    may not lose data silently (a full queue makes the producer wait, never drops)."""
    import zenoh
    return {"encoding": zenoh.Encoding.APPLICATION_JSON, "congestion_control": zenoh.CongestionControl.BLOCK,
            "reliability": zenoh.Reliability.RELIABLE}


RECONNECT = {"period_init_ms": 100, "period_max_ms": 1000, "period_increase_factor": 2}
"""How a session that lost a link to an endpoint it connects to tries again: after 0.1 s, doubling
to once a second. Zenoh's default waits up to 4 s between tries (1, 2, 4, 4 ...), so a producer
connected to a `gaps serve` that was killed and restarted reached it up to 4 s late, and after a
serve down 3-8 s, what it published in the first seconds had left its CACHE_S cache by then:
kill -9 trials with the serve listening lost events to gaps, or (the producer closing before it
reconnected) everything after the kill, where the serve connecting (it dials at once on start)
lost none (docs/serve.md "Restarts"). A try to a closed port costs a refused SYN."""

CACHE_S = 10.0
"""How long every producer keeps what it published, for an ingest that was down to fetch again
(issue 14: an ingest down for up to 10 s loses nothing). The cache is one per producer process
(sim_replay/recent_events.py), asked as store/cache_wire.py says."""
LIVE_PREFIX = "gaps/@live"
"""Where sources declare liveliness tokens, ``gaps/@live/<run>/<src>`` (DESIGN "Zenoh"). An @ chunk:
no ``gaps/**`` subscription matches it, so tokens never reach the event stream."""


def audit_publisher_options() -> dict[str, Any]:
    """What every event publisher is declared with (zenoh.ext.declare_advanced_publisher): the audit
    QoS and sequence numbers on every sample, so that an ingest that sees one skipped on a live link
    records the samples as lost (wire_misses).

    No Zenoh cache and no publisher detection, measured (docs/serve.md "Recovery"): each declares
    a queryable or a liveliness token per key, i.e. per source and kind, and a simulation's road
    users coming and going made the ingest's Zenoh thread spend most of a CPU on those
    declarations. The producer keeps one cache of its own instead (store/cache_wire.py). No
    heartbeat and no Zenoh recovery or history either: with recovery on, a link whose subscriber
    channel stayed full for seconds (the ingest's fills by design, pushing back on publishers)
    hung for good, and Zenoh's history hands over a cached sample only if no newer one of its
    publisher was delivered (zenoh 1.10.2)."""
    from zenoh import ext
    return {**audit_qos(), "sample_miss_detection": ext.MissDetectionConfig(heartbeat=None, sporadic_heartbeat=None)}


def live_key(run: str, src: str) -> str:
    """A source's liveliness token: ``gaps/@live/<run>/<src>``."""
    return f"{LIVE_PREFIX}/{run}/{src}"


def live_slice(key_expr: str) -> str:
    """The liveliness tokens of the sources an ingest's key expression receives: ``gaps/**`` watches
    ``gaps/@live/**``, a slice ``gaps/site-a/**`` watches ``gaps/@live/site-a/**``."""
    rest = key_expr.partition("/")[2] if key_expr.startswith("gaps/") else "**"
    return f"{LIVE_PREFIX}/{rest or '**'}"


def source_of_live_key(key: str) -> tuple[str, str] | None:
    """(run, src) of a liveliness token's key; None for a key of another shape."""
    if not key.startswith(LIVE_PREFIX + "/"):
        return None
    run, _, src = key[len(LIVE_PREFIX) + 1:].partition("/")
    return (run, src) if run and src.count("/") == 1 and all(src.split("/")) else None


def matched_within(entity: Any, within_s: float, poll_s: float = 0.01) -> bool:
    """Whether a publisher's subscriber (a querier's queryable) becomes known within `within_s`:
    declarations reach a session one by one after it opens. Zenoh 1.10 returns a MatchingStatus
    from `matching_status`, despite its stub saying bool."""
    deadline = time.monotonic() + within_s
    while True:
        status = entity.matching_status
        if bool(getattr(status, "matching", status)):
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(poll_s)


def zenoh_message(exc: BaseException) -> str:
    """Zenoh's error text without the Rust source location it appends (`... at /root/.cargo/...`)."""
    text = str(exc)
    cut = text.find(" at /")
    return (text[:cut] if cut > 0 else text).rstrip(".") or type(exc).__name__


MODES = ("peer", "client", "router")
ENDPOINT = re.compile(r"[a-z][a-z0-9+-]*/[^/?#\s][^\s]*")  # <protocol>/<address>[?<metadata>][#<config>]


def session_config(
    *,
    listen: Sequence[str] = (),
    connect: Sequence[str] = (),
    mode: str | None = None,
    config_file: str | os.PathLike | None = None,
) -> zenoh.Config:
    """Build the config. Without a file: ``mode`` (default peer), the endpoints given (``listen`` is
    always written out, so a peer never opens Zenoh's default any-port), no scouting, a put that
    waits BLOCK_FOR_US for room, and a lost link to a ``connect`` endpoint tried again as RECONNECT says. With a file: the file, and over it only ``mode``, ``listen`` and
    ``connect`` where they were given."""
    if mode is not None and mode not in MODES:
        raise WireConfigError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
    for endpoint in (*listen, *connect):
        if not ENDPOINT.fullmatch(endpoint):
            raise WireConfigError(f"endpoint {endpoint!r} is not of the form PROTOCOL/ADDRESS, "
                                  "e.g. tcp/127.0.0.1:7447")
    import zenoh
    if config_file is None:
        config = zenoh.Config()
        mode = mode or "peer"
        _insert(config, "scouting/multicast/enabled", False)
        _insert(config, "scouting/gossip/enabled", False)
        _insert(config, "listen/endpoints", list(listen))
        _insert(config, "transport/link/tx/queue/congestion_control/block/wait_before_close", BLOCK_FOR_US)
        _insert(config, "connect/retry", RECONNECT)
    else:
        config = _read(config_file)
        if listen:
            _insert(config, "listen/endpoints", list(listen))
    if mode is not None:
        _insert(config, "mode", mode)
    if connect or config_file is None:
        _insert(config, "connect/endpoints", list(connect))
    return config


def _read(path: str | os.PathLike) -> zenoh.Config:
    """The operator's file, or an error naming it and what Zenoh found wrong."""
    if not os.path.isfile(path):
        raise WireConfigError(f"no Zenoh config file at {os.fspath(path)}")
    import zenoh
    try:
        return zenoh.Config.from_file(os.fspath(path))
    except zenoh.ZError as exc:
        raise WireConfigError(f"cannot use the Zenoh config file {os.fspath(path)}: {zenoh_message(exc)}") from None


def _insert(config: zenoh.Config, key: str, value: object) -> None:
    """Write one setting; one Zenoh refuses is the user's mistake, said as such."""
    import zenoh
    try:
        config.insert_json5(key, json.dumps(value))
    except zenoh.ZError as exc:
        raise WireConfigError(f"Zenoh refuses {key} = {value!r}: {zenoh_message(exc)}") from None
