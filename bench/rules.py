"""Rules benchmark: permission queries per second, plain and with full proof trees.

The question is the paper's: "V can enter the junction" on a 10-fact Vehicle Scenario, against
the project's rulebook (reasoner/rules/paper.le), asked through the public Engine API exactly as
the investigation asks it (facts parsed once, as they are when a scenario is rebuilt).  Half the
questions are permitted (green light) and half are not (red light, so the proof mode also
builds the why-not tree).  Also: how long the rulebooks take to compile and load.

    .venv/bin/python bench/rules.py [--seconds 2] [--runs 5]

Targets (DESIGN "Performance and reliability targets"): >= 20,000 plain queries/s and
>= 2,000/s with full proof trees, single core.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from reasoner.bundled import bundled  # noqa: E402
from reasoner.engine import Engine, get_engine  # noqa: E402
from reasoner.le.document import parse_document  # noqa: E402
from reasoner.le.sentences import parse_fact  # noqa: E402
from machine import machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file

SCENARIO = [
    "{v} is of type car",
    "{v} has {colour} light",
    "{v} is on an emergency call",
    "301 is of type bus",
    "301 has red light",
    "301 is stopped",
    "302 is of type cyclist",
    "302 has green light",
    "303 is of type ambulance",
    "303 potentially violates enter the junction",
]




def questions(rb, n: int = 200):
    t = rb.document.templates
    out = []
    for i in range(n):
        v = str(1000 + i)
        colour = "green" if i % 2 == 0 else "red"
        facts = [parse_fact(s.format(v=v, colour=colour), t) for s in SCENARIO]
        assert all(facts) and len(facts) == 10
        out.append((parse_fact(f"{v} can enter the junction", t), facts))
    return out


def rate(fn, qs, seconds: float) -> tuple[float, float]:
    """(queries per wall-clock second, queries per CPU second of this process)."""
    done, start, cpu = 0, time.perf_counter(), time.process_time()
    while True:
        for goal, facts in qs:
            fn(goal, facts)
        done += len(qs)
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return done / elapsed, done / max(time.process_time() - cpu, 1e-9)


def compile_times(engine: Engine, text: str, name: str, runs: int) -> tuple[float, float]:
    parse = statistics.median(_timed(lambda: parse_document(text, name)) for _ in range(runs))
    loads = []
    for i in range(runs):
        variant = text + f"\n% run {i} {time.time_ns()}\n"      # a new text: a new module each time
        loads.append(_timed(lambda: engine.load(variant, name)))
    return parse, statistics.median(loads)


def _timed(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=0.3 if quick() else 2.0, help="length of one run")
    ap.add_argument("--runs", type=int, default=3 if quick() else 5, help="runs per figure (the median is reported)")
    args = ap.parse_args()

    engine = get_engine()
    rb = engine.load(bundled("paper.le"), "paper.le")
    qs = questions(rb)
    expected = [engine.holds(rb, g, f) for g, f in qs]
    assert expected == [i % 2 == 0 for i in range(len(qs))], "the rulebook no longer answers as the paper says"
    assert all(engine.ask(rb, g, f).holds == e for (g, f), e in zip(qs, expected))

    plain = [rate(lambda g, f: engine.holds(rb, g, f), qs, args.seconds) for _ in range(args.runs)]
    proofs = [rate(lambda g, f: engine.ask(rb, g, f), qs, args.seconds) for _ in range(args.runs)]
    version = engine._janus.query_once("current_prolog_flag(version, V)")["V"]

    swipl = f"SWI-Prolog {version // 10000}.{version // 100 % 100}.{version % 100}"
    load_avg = f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}"
    print(f"machine: {machine()}, {swipl}, {load_avg}")
    print("question: \"V can enter the junction\" on a 10-fact scenario, half permitted, rulebook paper.le, "
          "one thread")
    figures = []
    for label, runs, target, peer in (("plain (Engine.holds)", plain, "20,000/s", ""),
                                      ("with proof trees (Engine.ask)", proofs, "2,000/s", "plain (Engine.holds)")):
        wall = [w for w, _ in runs]
        cpu = [c for _, c in runs]
        print(f"{label:31s} median {statistics.median(wall):>9,.0f} queries/s wall clock "
              f"(runs: {', '.join(f'{r:,.0f}' for r in wall)}), "
              f"{statistics.median(cpu):,.0f} per CPU second; target {target.removesuffix('/s')}")
        figures.append(Figure(label, statistics.median(wall), "queries/s", tuple(wall), target, peer,
                              note=f"{statistics.median(cpu):,.0f} per CPU second"))
    for name, text in [("paper.le", bundled("paper.le"))] + _conformance_largest():
        parse, load = compile_times(engine, text, name, args.runs)
        rules = len(parse_document(text, name).rules)
        print(f"compile {name} ({rules} rules, {len(text):,} chars): parse median {parse * 1000:.1f} ms, "
              f"parse and load median {load * 1000:.1f} ms")
        figures.append(Figure(f"compile and load {name} ({rules} rules, {len(text):,} chars)", load * 1000, "ms",
                              note=f"parse alone {parse * 1000:.1f} ms"))
    record("rules", "Logical English queries and compilation", figures, machine_extra=f"{swipl}, {load_avg}",
           notes=f"\"V can enter the junction\" on a 10-fact scenario, half permitted, rulebook paper.le, one "
                 f"thread; {args.runs} runs of {args.seconds:g} s per figure")


def _conformance_largest():
    suite = ROOT.parent / "shared/le/conformance"
    docs = sorted(suite.glob("*.le"), key=lambda p: -p.stat().st_size) if suite.is_dir() else []
    for p in docs:
        if p.name != "error.le":
            return [(p.name, p.read_text(encoding="utf-8"))]
    return []


if __name__ == "__main__":
    main()
