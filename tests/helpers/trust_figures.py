"""Figures for issue 37: rewrites and forged tails of a signed, witnessed store, made by someone
who holds the store file but not the checkpoint key (tests/helpers/trust_attacks.py), each tried
N times with fresh choices (which checkpoint is kept, which id, how many events are forged, which
event is changed), and how many of them `gaps verify`, `--key PUB`, `--against WITNESS` and both
catch (exit 1). For the forged tails at id 0 and 100, how often the honest append on top (as
`gaps serve --checkpoint-key KEY --witness W` makes it) was stored; the sealed one is written by
hand as the ingest before issue 37 wrote it, so it is sealed every time.

    .venv/bin/python tests/helpers/trust_figures.py [N]                               # this checkout
    GAPS_TREE=/path/to/other/checkout .venv/bin/python tests/helpers/trust_figures.py [N]  # another one

The second form counts what another version catches with the same attacks (its own store, CLI and
tests/helpers/cli.py; the attacks use only what every version of the store offers). It lives
beside the attacks, not in bench/: these are counts, not timings, and nothing goes to
bench/results.json.
"""
from __future__ import annotations

import os
import random
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[2]
TREE = Path(os.environ.get("GAPS_TREE", HERE)).resolve()
sys.path.insert(0, str(TREE))


def _attacks():
    """The attacks module of this checkout, loaded by its path (another tree may not have it)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("trust_attacks", HERE / "tests" / "helpers" / "trust_attacks.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["trust_attacks"] = module
    spec.loader.exec_module(module)
    return module


def main(n: int) -> None:
    attacks = _attacks()
    started = time.monotonic()
    table = []
    with tempfile.TemporaryDirectory() as folder:
        base = Path(folder)
        for name in attacks.ATTACKS:
            tried = appended = 0
            caught = {check: 0 for check in attacks.CHECKS}
            for trial in range(n):
                honest = attacks.honest_store(base / f"h-{len(table)}-{trial}")
                done = attacks.attack(name, honest, base / f"a-{len(table)}-{trial}.db", random.Random(trial))
                tried += 1
                appended += bool(done.appended)
                for check, passed in attacks.passes(done, honest.public).items():
                    caught[check] += not passed
            table.append((name, tried, appended if done.appended is not None else None, caught))
    print(f"store and CLI of {TREE}; {n} tries of each attack ({time.monotonic() - started:.0f} s)")
    checks = list(attacks.CHECKS)
    header = ["attack", "tried", "honest append stored", *(f"caught by {c}" for c in checks)]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for name, tried, appended, caught in table:
        cells = [name, str(tried), "-" if appended is None else str(appended), *(str(caught[c]) for c in checks)]
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
