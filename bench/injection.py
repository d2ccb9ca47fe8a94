"""Injection attempts by a stranger on the network against an ingest, and how many got through
(issue 37's figures; a check of security, not of speed; tests/ingest/test_exposure.py and
tests/ingest/test_hardened_deployment.py test the same things one by one).

    .venv/bin/python bench/injection.py [--events 20]

Three set-ups, each a fresh store, on loopback:
- `open`: an ingest without --require-signatures, as a serve ran by default before it refused to
  start open beyond loopback (on loopback it still runs so);
- `signatures`: the same with --require-signatures (a keys file for vehicle/173 and vehicle/174);
- `hardened`: docs/serve.md's hardened deployment: a Zenoh router with mutual TLS and an access
  control list, the ingest its client with signatures required; the stranger holds a certificate
  of the same authority under another name (one with none is not let in at all: the test).

The stranger, a Zenoh session of its own, tries: `--events` events as vehicle/174 (a source with a
key that publishes nothing); the next `--events` seqs of vehicle/173 before the real producer
publishes them (which would have the real ones quarantined as conflicting duplicates); a
liveliness token for vehicle/174 (keyed) and one for vehicle/999 (no key), declared then
withdrawn; a history query on `gaps/**`. Counted from the store and the query's answer.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import zenoh  # noqa: E402

from ingest import IngestService  # noqa: E402
from results import Figure, record  # noqa: E402
from sim_replay.publisher import EventPublisher, zenoh_config  # noqa: E402
from store import Store, canonical_json
from store.keys import KeyFolder, Signer, TrustedKeys
from store.wire import session_config  # noqa: E402
from tests.helpers.hardened import deployment, openssl  # noqa: E402
from tests.helpers.ingest_testkit import RUN, free_endpoint, make_event  # noqa: E402

SETUPS = ("open", "signatures", "hardened")
SETTLE_S = 1.5


@dataclass(frozen=True)
class Outcome:
    """What got through of each attempt in one set-up (tried: how many were tried)."""

    setup: str
    tried: int
    stored_as_vehicle: int        # the stranger's events stored as vehicle/174
    next_seqs_taken: int          # the stranger's versions of vehicle/173's next seqs stored
    real_quarantined: int         # the real producer's events then refused as conflicting duplicates
    real_stored: int              # of the real producer's 5 + tried events
    stranger_quarantined: int     # the stranger's events refused and kept in the quarantine
    tokens_recorded: int          # liveliness changes recorded for the stranger's two tokens (of 4)
    history_replies: int          # stored events the stranger's history query received

    def to_json(self) -> dict:
        return asdict(self)


def attempt(workdir: Path, setup: str, n: int) -> Outcome:
    keys = KeyFolder(workdir / "keys")
    for src in ("vehicle/173", "vehicle/174"):
        keys.create(src)
    trusted = TrustedKeys.load(keys.write_public_keys()) if setup != "open" else None
    db = workdir / "gaps.db"
    router = None
    if setup == "hardened":
        made = deployment(workdir / "deploy")
        router = zenoh.open(session_config(config_file=made.config("router")))
        ingest = IngestService(db, config_file=made.config("ingest"), trusted_keys=trusted)
        producer_config = session_config(config_file=made.config("producer"))
        stranger_config = session_config(config_file=made.config("stranger"))
    else:
        endpoint = free_endpoint()
        ingest = IngestService(db, listen=[endpoint], trusted_keys=trusted)
        producer_config = stranger_config = zenoh_config(connect=[endpoint])
    try:
        producer = EventPublisher(config=producer_config, signer=Signer(keys))
        stranger = zenoh.open(stranger_config)
        time.sleep(0.5)     # declarations go round
        producer.publish_all([make_event("vehicle/173", seq) for seq in range(5)])
        for seq in range(n):
            stranger.put(f"gaps/{RUN}/vehicle/174/vehicle.perception", canonical_json(make_event("vehicle/174", seq)))
        for seq in range(5, 5 + n):
            stranger.put(f"gaps/{RUN}/vehicle/173/vehicle.perception",
                         canonical_json(make_event("vehicle/173", seq, facts=["173 has green light"])))
        tokens = [stranger.liveliness().declare_token(f"gaps/@live/{RUN}/{src}") for src in ("vehicle/174", "vehicle/999")]
        time.sleep(SETTLE_S)
        replies = sum(1 for r in stranger.get("gaps/**", target=zenoh.QueryTarget.ALL,
                                              consolidation=zenoh.ConsolidationMode.NONE, timeout=5) if r.ok is not None)
        for token in tokens:
            token.undeclare()
        producer.publish_all([make_event("vehicle/173", seq) for seq in range(5, 5 + n)])
        producer.close()
        time.sleep(SETTLE_S)
        stranger.close()
    finally:
        ingest.stop()
        if router is not None:
            router.close()
    with Store.open_read_only(db) as store:
        events = list(store.events(RUN))
        quarantine = store.quarantined()
        tokens_recorded = sum(len(store.liveliness_changes(RUN, src)) for src in ("vehicle/174", "vehicle/999"))
    taken = sum(1 for e in events if e["src"] == "vehicle/173" and "173 has green light" in e["body"].get("facts", []))
    return Outcome(setup, n, sum(1 for e in events if e["src"] == "vehicle/174"), taken,
                   sum(row["count"] for row in quarantine if "conflicting duplicate" in row["reason"]
                       and b'"src":"vehicle/173"' in row["raw"] and b"173 has green light" not in row["raw"]),
                   sum(1 for e in events if e["src"] == "vehicle/173") - taken,
                   sum(row["count"] for row in quarantine if b'"src":"vehicle/174"' in row["raw"]
                       or b"173 has green light" in row["raw"]), tokens_recorded, replies)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20, help="events tried per attempt")
    args = parser.parse_args()
    setups = SETUPS if openssl() else SETUPS[:2]
    outcomes = []
    for setup in setups:
        with tempfile.TemporaryDirectory() as tmp:
            outcomes.append(attempt(Path(tmp), setup, args.events))
    n = args.events
    rows = [("events as vehicle/174 stored", "stored_as_vehicle", n),
            ("vehicle/173's next seqs taken by the stranger", "next_seqs_taken", n),
            ("  the real ones then quarantined", "real_quarantined", n),
            ("  the real producer's events stored", "real_stored", n + 5),
            ("the stranger's events refused into the quarantine", "stranger_quarantined", 2 * n),
            ("liveliness changes recorded (2 tokens, declared and withdrawn)", "tokens_recorded", 4),
            ("stored events the stranger's history query received", "history_replies", None)]
    print("| attempt (got through) | " + " | ".join(o.setup for o in outcomes) + " |")
    print("|---|" + "---|" * len(outcomes))
    for label, field_name, of in rows:
        cells = [f"{getattr(o, field_name)}" + (f" of {of}" if of is not None else "") for o in outcomes]
        print(f"| {label} | " + " | ".join(cells) + " |")
    record("injection", "a stranger's injection attempts against an ingest, open, with signatures, hardened",
           [Figure(f"{o.setup}: {label.strip()}", getattr(o, f), "events" if "liveliness" not in label else "changes")
            for o in outcomes for label, f, _ in rows],
           notes=f"{n} events an attempt", details={"outcomes": [o.to_json() for o in outcomes]})


if __name__ == "__main__":
    main()
