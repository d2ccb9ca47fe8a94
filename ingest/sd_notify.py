"""Tell systemd how the service is doing (``Type=notify``): READY once it receives, STATUS each tick,
STOPPING while it flushes. The protocol is one datagram on the socket named by ``$NOTIFY_SOCKET``; without
that variable (not under systemd) nothing is sent. Written out here rather than taken from a library: it
is these few lines."""
from __future__ import annotations

import os
import socket


def notify(state: str) -> bool:
    """Send ``state`` (e.g. ``READY=1``); True if a supervisor took it. Never raises and never
    waits: a service must not fall over, nor hang on its way down, because its supervisor's socket
    went away or stopped reading (a datagram socket's queue holds a few messages: 10 by default)."""
    address = os.environ.get("NOTIFY_SOCKET")
    if not address:
        return False
    if address.startswith("@"):  # an abstract socket
        address = "\0" + address[1:]
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM | socket.SOCK_CLOEXEC | socket.SOCK_NONBLOCK) as sock:
            sock.connect(address)
            sock.send(state.encode())   # a full queue (a supervisor not reading) drops it: never wait
    except OSError:
        return False
    return True
