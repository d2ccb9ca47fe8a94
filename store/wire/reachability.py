"""Whether a gaps session (an ingest's or a producer's) can be reached from beyond this machine,
read from the Zenoh config it opens with, and what a producer so reached still lacks.

Secure by default (DESIGN "Zenoh"): on loopback anything goes. Reachable means: an endpoint it
listens on or connects to that is not on 127.0.0.0/8, ::1 or `localhost` (a Unix socket is local),
or multicast scouting on (a peer's or router's finds and links peers nobody named, a client's finds
routers), or gossip scouting on in peer or router mode. Read from the Zenoh config the session is
opened with (store.session_config: the command line's endpoints, or an operator's file with them
written over it), so a file that opens Zenoh's default any-address listener counts as it should.

The reading is here, in the store, because both sides need it and the store is the room both may
import: the ingest's rule (signatures and Zenoh authentication) is ingest/exposure.py's; the
producer's is `check_producer` below.
"""
from __future__ import annotations

import ipaddress
import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .contract import WireConfigError

if TYPE_CHECKING:
    import zenoh

LOCAL_PROTOCOLS = ("unixsock-stream", "unixpipe", "vsock")
INSECURE_FLAG = "--insecure-beyond-loopback"


@dataclass(frozen=True)
class Exposure:
    """What a session's config opens to the network: why it is reachable beyond loopback (empty: it
    is not), and what authenticates who reaches it (empty: nothing does)."""

    reachable: tuple[str, ...]
    authenticated_by: tuple[str, ...]

    def to_json(self) -> dict[str, Any]:
        return {"beyond_loopback": list(self.reachable), "authenticated_by": list(self.authenticated_by)}


def is_loopback(endpoint: str) -> bool:
    """Whether a Zenoh endpoint (``proto/address[?metadata][#config]``) stays on this machine."""
    proto, _, address = endpoint.partition("/")
    if proto in LOCAL_PROTOCOLS:
        return True
    address = address.split("?", 1)[0].split("#", 1)[0]
    if address.startswith("["):
        host = address[1:].partition("]")[0]
    else:
        host = address.rpartition(":")[0] if ":" in address else address
    if host.lower() == "localhost":
        return True
    try:
        ip = ipaddress.ip_address(host.partition("%")[0])
    except ValueError:   # a host name: it may resolve anywhere
        return False
    mapped = getattr(ip, "ipv4_mapped", None)   # ::ffff:127.0.0.1 is 127.0.0.1
    return (mapped or ip).is_loopback


def exposure(config: zenoh.Config) -> Exposure:
    """Read what ``config`` opens (see the module's doc)."""
    mode = _get(config, "mode") or "peer"
    reachable = [f"listens on {e}" for e in _endpoints(config, "listen", mode) if not is_loopback(e)]
    reachable += [f"connects to {e}" for e in _endpoints(config, "connect", mode) if not is_loopback(e)]
    for kind in ("multicast", "gossip"):   # a client scouts for routers by multicast; gossip is peers'
        if (kind == "multicast" or mode != "client") and _get(config, f"scouting/{kind}/enabled") is not False:
            reachable.append(f"{kind} scouting is on ({mode} mode)")   # Zenoh's default is on
    authenticated = []
    if _get(config, "access_control/enabled") is True:
        authenticated.append("access control (ACL)")
    if _get(config, "transport/link/tls/enable_mtls") is True:
        authenticated.append("mutual TLS")
    usrpwd = _get(config, "transport/auth/usrpwd") or {}
    if usrpwd.get("dictionary_file") or usrpwd.get("user"):
        authenticated.append("user/password")
    return Exposure(tuple(reachable), tuple(authenticated))


def check_producer(found: Exposure, *, signed: bool, insecure: bool) -> list[str]:
    """What a producer reachable beyond loopback lacks (nothing on loopback, or behind Zenoh's
    authentication); a WireConfigError saying so, unless ``insecure`` (the operator's explicit
    opt-out), in which case the list is returned for the log.

    Signing its events authenticates the events (an ingest requiring signatures stores no forged
    one), so a signing producer lacks only what signatures cannot cover: its cache's queryable
    answers whoever asks with the events of its last seconds, and whoever reaches it can declare
    its sources' liveliness tokens. Those need Zenoh's authentication whatever signs the events."""
    if not found.reachable or found.authenticated_by:
        return []
    missing = []
    if not signed:
        missing.append("its events are not signed (--sign-keys DIR): whoever it reaches takes them as its sources'")
    missing.append("its Zenoh config authenticates nobody (no access_control, mutual TLS or user/password in "
                   "--config): anyone reaching it can read its cache's recent events and declare its sources' "
                   "liveliness")
    if not insecure:
        raise WireConfigError(
            f"this producer can be reached beyond loopback ({'; '.join(found.reachable)}), and "
            f"{'; and '.join(missing)}. Fix that (docs/serve.md \"A hardened deployment\": --config with the "
            f"producer's certificate), use 127.0.0.1, or say {INSECURE_FLAG} to run it open anyway (logged)")
    return missing


def _endpoints(config: zenoh.Config, section: str, mode: str) -> Sequence[str]:
    """A section's endpoints: a list, or per mode (Zenoh's defaults are written so)."""
    value = _get(config, f"{section}/endpoints")
    if isinstance(value, dict):
        value = value.get(mode) or []
    return [str(e) for e in value or []]


def _get(config: zenoh.Config, key: str) -> Any:
    import zenoh
    try:
        return json.loads(config.get_json(key))
    except (zenoh.ZError, ValueError):
        return None
