"""Tell systemd how the service is doing (``Type=notify``): READY once it receives, STATUS each tick,
STOPPING while it flushes. The protocol is one datagram on the socket named by ``$NOTIFY_SOCKET``; without
that variable (not under systemd) nothing is sent. Written out here rather than taken from a library: it
is these few lines."""
from __future__ import annotations

import os
import socket


def notify(state: str) -> bool:
    """Send ``state`` (e.g. ``READY=1``); True if a supervisor is listening. Never raises: a service
    must not fall over because its supervisor's socket went away."""
    address = os.environ.get("NOTIFY_SOCKET")
    if not address:
        return False
    if address.startswith("@"):  # an abstract socket
        address = "\0" + address[1:]
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM | socket.SOCK_CLOEXEC) as sock:
            sock.connect(address)
            sock.sendall(state.encode())
    except OSError:
        return False
    return True
