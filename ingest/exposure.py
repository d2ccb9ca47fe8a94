"""Whether a `gaps serve` can be reached from beyond this machine, and whether it may then start.

Secure by default (DESIGN "Zenoh"): on loopback anything goes; an ingest that a stranger on the
network could reach must (a) require signatures, so that nobody stores events as a vehicle or a
monitor, or pre-publishes a source's next seqs to get the real ones quarantined, and (b) sit behind
Zenoh's own authentication or access control (mutual TLS, user/password, or an ACL in its config),
so that nobody reads its history or declares a source's liveliness token unchecked. Without both it
refuses to start, unless the operator says `--insecure-beyond-loopback`, which is logged.

What is reachable, and what authenticates, is read from the Zenoh config by store/reachability.py
(a producer is held to its own rule there); the rule for an ingest is this module's.
"""
from __future__ import annotations

from store.wire import INSECURE_FLAG, LOCAL_PROTOCOLS, Exposure, exposure, is_loopback  # noqa: F401 (the ingest's names)

from .errors import IngestConfigError

__all__ = ["INSECURE_FLAG", "LOCAL_PROTOCOLS", "Exposure", "check", "exposure", "is_loopback"]


def check(found: Exposure, *, signatures_required: bool, insecure: bool) -> list[str]:
    """What is missing for a serve reachable beyond loopback (nothing for one on loopback); an
    IngestConfigError saying so, unless ``insecure`` (the operator's explicit opt-out), in which
    case the list is returned for the log."""
    if not found.reachable:
        return []
    missing = []
    if not signatures_required:
        missing.append("signatures are not required (--require-signatures KEYS): anyone reaching it can store "
                       "events as any source and pre-publish a source's next seqs")
    if not found.authenticated_by:
        missing.append("its Zenoh config authenticates nobody (no access_control, mutual TLS or user/password in "
                       "--config): anyone reaching it can read its history and declare a source's liveliness")
    if missing and not insecure:
        raise IngestConfigError(
            f"this serve can be reached beyond loopback ({'; '.join(found.reachable)}), and "
            f"{'; and '.join(missing)}. Fix that (docs/serve.md \"A hardened deployment\"), listen on 127.0.0.1, "
            f"or say {INSECURE_FLAG} to run it open anyway (logged)")
    return missing
