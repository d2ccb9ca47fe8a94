"""docs/serve.md's hardened deployment, built on loopback from the docs' own files: a certificate
authority and certificates made with openssl in a folder, the router's and the serve's Zenoh
configs taken from the ```json5 blocks of docs/serve.md with the paths and the router's address
put in, and a client config per role (the serve's with another certificate), so that what the
docs show is what the tests run (tests/ingest/test_hardened_deployment.py, bench/injection.py)."""
from __future__ import annotations

import re
import shutil
import socket
import subprocess
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).parents[2]
DOC = ROOT / "docs" / "serve.md"
DOC_TLS_DIR = "/etc/gaps/tls/"
DOC_ROUTER_LISTEN = "tls/0.0.0.0:7447"
DOC_ROUTER_DIALED = "tls/router.example.org:7447"
ROLES = ("router", "ingest", "producer", "reader", "stranger")


def openssl() -> str | None:
    return shutil.which("openssl")


def doc_block(name: str) -> str:
    """The ```json5 NAME block of docs/serve.md."""
    found = re.search(rf"^```json5 {re.escape(name)}\n(.*?)^```$", DOC.read_text("utf-8"), re.S | re.M)
    if found is None:
        raise AssertionError(f"docs/serve.md has no ```json5 {name} block")
    return found.group(1)


def make_certificates(folder: Path) -> None:
    """A CA and a certificate per role, each named by its CN, valid for localhost and 127.0.0.1
    (the docs' commands, with the loopback names in subjectAltName)."""
    folder.mkdir(parents=True, exist_ok=True)

    def run(*args: str) -> None:
        subprocess.run([openssl(), *args], cwd=folder, check=True, capture_output=True)

    ec = ("-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes")
    run("req", "-x509", *ec, "-keyout", "ca.key", "-out", "ca.pem", "-days", "2", "-subj", "/CN=gaps-test-ca")
    for cn in ROLES:
        run("req", *ec, "-keyout", f"{cn}.key", "-out", f"{cn}.csr", "-subj", f"/CN={cn}")
        (folder / f"{cn}.ext").write_text("subjectAltName=DNS:localhost,IP:127.0.0.1\n"
                                          "extendedKeyUsage=serverAuth,clientAuth\n")
        run("x509", "-req", "-in", f"{cn}.csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
            "-out", f"{cn}.pem", "-days", "2", "-extfile", f"{cn}.ext")


@dataclass(frozen=True)
class Deployment:
    """The files of one deployment: ``config(role)`` is a role's Zenoh config file."""

    folder: Path
    endpoint: str     # tls/127.0.0.1:<port>, where the router listens

    def config(self, role: str) -> Path:
        return self.folder / f"{role}.json5"


def deployment(folder: Path) -> Deployment:
    """Certificates and configs in ``folder``, for a router on a free loopback port."""
    tls = folder / "tls"
    make_certificates(tls)
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        endpoint = f"tls/127.0.0.1:{sock.getsockname()[1]}"
    made = Deployment(folder, endpoint)

    def local(text: str) -> str:
        return (text.replace(DOC_TLS_DIR, f"{tls}/").replace(DOC_ROUTER_LISTEN, endpoint)
                .replace(DOC_ROUTER_DIALED, endpoint))

    made.config("router").write_text(local(doc_block("router.json5")))
    serve = local(doc_block("serve.json5"))
    for role in ROLES[1:]:
        made.config(role).write_text(serve.replace(f"{tls}/ingest.", f"{tls}/{role}."))
    # a client with no certificate of its own: the serve's file without the mutual TLS part
    made.config("outsider").write_text(re.sub(r"\s*connect_private_key:[^\n]*\n\s*connect_certificate:[^\n]*\n",
                                              "\n", serve))
    return made
