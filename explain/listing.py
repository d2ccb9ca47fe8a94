"""Incidents as a list to scan: one line each, filters, and the full explanations on request.

`gaps incidents` prints one line per incident so that an investigator sees a whole run at a
glance and then asks `gaps explain` about the one that matters. The line is drawn from the
incident's JSON shape (what `gaps incidents --json` prints), read key by key, so a renamed key
fails loudly here rather than printing a blank.
"""
from __future__ import annotations

from typing import Any, Callable, Iterable, Iterator

from reasoner.when import format_time

VERDICTS = ("punishable", "mitigated", "dismissed")
INTERNAL = ("proofs", "scenarios")   # what the JSON output leaves out: proof trees and raw scenarios


def incident_json(inc: dict[str, Any]) -> dict[str, Any]:
    """The incident as `gaps incidents --json` prints it (an Incident's to_json() where there is one)."""
    return {k: v for k, v in inc.items() if k not in INTERNAL}


def numbered(incidents: Iterable[dict[str, Any]]) -> list[tuple[int, dict[str, Any]]]:
    """Each incident with its number within its run: the number `gaps explain --run R N` takes."""
    counts: dict[str, int] = {}
    out = []
    for inc in incidents:
        counts[inc["run"]] = counts.get(inc["run"], 0) + 1
        out.append((counts[inc["run"]], inc))
    return out


def matches(d: dict[str, Any], verdict: str | None = None, vehicle: str | None = None,
            rule: str | None = None) -> bool:
    """Whether the incident passes the filters given (None: any); rules compare without case."""
    return ((verdict is None or d["verdict"] == verdict)
            and (vehicle is None or d["vehicle"] == vehicle)
            and (rule is None or str(d["rule"]).casefold() == rule.casefold()))


def incident_line(d: dict[str, Any], number: int | None = None) -> str:
    """One incident in one line: number, time, id, vehicle, action, rule, verdict, penalty,
    who is liable, the margin where the incident has one, and its findings."""
    fields = [format_time(d["t"]), d["id"], f"vehicle {d['vehicle']}", d["action"], str(d["rule"]),
              d["verdict"], _penalty(d["penalty"]), f"liable: {d['liable']}"]
    if _has_margin(d):
        fields.append(f"margin {_margin(d['margin'])}")
    fields.append(_findings(d["findings"]))
    line = "  ".join(fields)
    return f"{number:>3}  {line}" if number is not None else line


def explanations(incidents: list[dict[str, Any]], rulebooks: Callable[[str], Any],
                 store: Any) -> Iterator[str]:
    """The full text explanation of each incident under a numbered heading, each run's chain
    verified once for all its incidents."""
    from . import explain_incident
    from .evidence import chain_status
    chains = {r: chain_status(store, r) for r in {inc["run"] for inc in incidents}}
    for n, inc in enumerate(incidents, 1):
        yield (f"── incident {n}: {inc['run']} {inc['id']} ──\n"
               + explain_incident(inc, rulebooks, store, chain=chains[inc["run"]]) + "\n")


def _penalty(p: dict[str, Any] | None) -> str:
    if p is None:
        return "no penalty"
    parts = [f"£{p['fine_gbp']}" if p["fine_gbp"] is not None else None,
             f"{p['points']} points" if p["points"] else None]
    return " + ".join(part for part in parts if part) or p["offence"]


def _has_margin(d: dict[str, Any]) -> bool:
    """A margin is measured only by rules with a quantity (a speed, a distance); other incidents
    carry none, or no key at all."""
    return "margin" in d and d["margin"] is not None


def _margin(m: Any) -> str:
    if isinstance(m, dict):
        return ", ".join(f"{k} {v}" for k, v in m.items())
    return str(m)


def _findings(findings: list[dict[str, Any]]) -> str:
    if not findings:
        return "no findings"
    names = ", ".join(f["kind"] for f in findings)
    return f"{len(findings)} finding{'s' if len(findings) != 1 else ''}: {names}"
