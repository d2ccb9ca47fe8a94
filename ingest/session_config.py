"""The ingest's Zenoh configuration: explicit endpoints only, no scouting.

An audit ingest should receive from the producers it was pointed at, not from whatever answers a multicast
probe; and ``gaps serve --listen/--connect`` maps one to one onto these arguments.
"""
from __future__ import annotations

import json
from collections.abc import Sequence

import zenoh

MODES = ("peer", "client", "router")


def session_config(
    *, listen: Sequence[str] = (), connect: Sequence[str] = (), mode: str = "peer"
) -> zenoh.Config:
    """Build the config; ``listen`` is always written out so a peer never opens Zenoh's default any-port."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
    config = zenoh.Config()
    config.insert_json5("mode", json.dumps(mode))
    config.insert_json5("listen/endpoints", json.dumps(list(listen)))
    config.insert_json5("connect/endpoints", json.dumps(list(connect)))
    config.insert_json5("scouting/multicast/enabled", "false")
    config.insert_json5("scouting/gossip/enabled", "false")
    return config
