"""The ingest's Zenoh configuration: explicit endpoints only, no scouting, unless an operator's file says otherwise.

An audit ingest should receive from the producers it was pointed at, not from whatever answers a multicast
probe; and ``gaps serve --listen/--connect`` maps one to one onto these arguments. An operator with a
Zenoh config file of their own (``gaps serve --config zenoh.json5``: TLS, access control, tuned
transports) gets exactly that file, with only the options given on the command line written over it.
"""
from __future__ import annotations

import json
import os
import re
from collections.abc import Sequence

import zenoh

from .errors import IngestConfigError, zenoh_message

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
    always written out, so a peer never opens Zenoh's default any-port) and no scouting. With a file:
    the file, and over it only ``mode``, ``listen`` and ``connect`` where they were given."""
    if mode is not None and mode not in MODES:
        raise IngestConfigError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
    for endpoint in (*listen, *connect):
        if not ENDPOINT.fullmatch(endpoint):
            raise IngestConfigError(f"endpoint {endpoint!r} is not of the form PROTOCOL/ADDRESS, "
                                    "e.g. tcp/127.0.0.1:7447")
    if config_file is None:
        config = zenoh.Config()
        mode = mode or "peer"
        _insert(config, "scouting/multicast/enabled", False)
        _insert(config, "scouting/gossip/enabled", False)
        _insert(config, "listen/endpoints", list(listen))
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
        raise IngestConfigError(f"no Zenoh config file at {os.fspath(path)}")
    try:
        return zenoh.Config.from_file(os.fspath(path))
    except zenoh.ZError as exc:
        raise IngestConfigError(f"cannot use the Zenoh config file {os.fspath(path)}: {zenoh_message(exc)}") from None


def _insert(config: zenoh.Config, key: str, value: object) -> None:
    """Write one setting; one Zenoh refuses is the user's mistake, said as such."""
    try:
        config.insert_json5(key, json.dumps(value))
    except zenoh.ZError as exc:
        raise IngestConfigError(f"Zenoh refuses {key} = {value!r}: {zenoh_message(exc)}") from None
