"""Private keys are read and written by `cryptography`'s PKCS#8 serialisation, not a hand-built
DER prefix (issue 39): every Ed25519 key PKCS#8 allows is read, and anything else is refused by
name."""
from __future__ import annotations

import subprocess

import pytest

from store.keys.files import KeyFolder, KeysError, pem_of, seed_of

# RFC 8410 section 10.3: an Ed25519 private key with its public key and an attribute (PKCS#8 v2,
# OneAsymmetricKey). The prefix this module once compared bytes with refused it.
RFC8410_WITH_PUBLIC_KEY = """-----BEGIN PRIVATE KEY-----
MHICAQEwBQYDK2VwBCIEINTuctv5E1hK1bbY8fdp+K06/nwoy/HU++CXqI9EdVhC
oB8wHQYKKoZIhvcNAQkJFDEPDA1DdXJkbGUgQ2hhaXJzgSEAGb9ECWmEzf6FQbrB
Z9w7lshQhqowtrbLDFw4rXAxZuE=
-----END PRIVATE KEY-----
"""
RFC8410_SEED = bytes.fromhex("d4ee72dbf913584ad5b6d8f1f769f8ad3afe7c28cbf1d4fbe097a88f44755842")


def test_the_rfc_8410_example_with_its_public_key_is_read():
    assert seed_of(RFC8410_WITH_PUBLIC_KEY, "rfc8410.pem") == RFC8410_SEED


def test_a_key_written_reads_back_and_is_the_rfc_8410_form():
    seed = bytes(range(32))
    pem = pem_of(seed)
    assert pem.startswith("-----BEGIN PRIVATE KEY-----\n") and seed_of(pem, "k") == seed
    assert len(pem.splitlines()) == 3                  # 48 bytes of DER: one base64 line


def test_another_kind_of_key_is_refused_by_name(tmp_path):
    ec = tmp_path / "ec.key"
    subprocess.run(["openssl", "genpkey", "-algorithm", "EC", "-pkeyopt", "ec_paramgen_curve:P-256", "-out", str(ec)],
                   check=True, capture_output=True)
    with pytest.raises(KeysError, match=r"ec.key: not an Ed25519 private key \(it is an EC"):
        seed_of(ec.read_text(), str(ec))


@pytest.mark.parametrize("text, said", [("hello", "not a private key in PEM"),
                                        ("-----BEGIN PRIVATE KEY-----\n!!\n-----END PRIVATE KEY-----\n",
                                         "not a private key in PEM")])
def test_what_is_not_a_key_is_said(text, said):
    with pytest.raises(KeysError, match=said):
        seed_of(text, "k.key")


def test_an_encrypted_key_says_it_needs_a_password(tmp_path):
    key = tmp_path / "enc.key"
    subprocess.run(["openssl", "genpkey", "-algorithm", "ed25519", "-aes256", "-pass", "pass:x", "-out", str(key)],
                   check=True, capture_output=True)
    with pytest.raises(KeysError, match="encrypted"):
        seed_of(key.read_text(), str(key))
    assert KeyFolder(tmp_path)      # the folder itself is fine
