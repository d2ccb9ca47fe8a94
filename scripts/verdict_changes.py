"""Every verdict that changed between two judgements of one run, with the reason the new one gives.

    gaps incidents --run R --json --db COPY > new.json              (this checkout)
    OLD/.venv/bin/gaps incidents --run R --json --db COPY > old.json (an older checkout, same store copy)
    .venv/bin/python scripts/verdict_changes.py old.json new.json [--json]

Issue 36 asks for every verdict that changed on the demo and two simulated runs, listed with its
reason. An older judgement may hold several incidents for what is now one act (one act, one
offence), so an old incident is matched to the new incident of the same vehicle and action
whose act (`act.start`..`act.end`, else its time) holds the old one's time, within SLACK_S; the
nearest in time where several do. Printed, per old incident: the same verdict (counted), a
changed verdict with the new one's rule, margin and its `why` (the reason the reasoner gives),
merged into an act another old incident also went to, or gone (no new incident of that act);
and every new incident no old one went to (an act found now that was not raised before, with
where it was found).
"""
from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from datetime import datetime, timezone
from typing import Any

SLACK_S = 1.5
SECOND = 1_000_000_000


def span(inc: dict[str, Any]) -> tuple[int, int]:
    act = inc.get("act") or {}
    start, end = act.get("start"), act.get("end")
    return (start if isinstance(start, int) else inc["t"], end if isinstance(end, int) else inc["t"])


def match(old: dict[str, Any], new: list[dict[str, Any]]) -> int | None:
    """The index of the new incident the old one's act became, or None."""
    best: tuple[float, int] | None = None
    for i, inc in enumerate(new):
        if inc["vehicle"] != old["vehicle"] or inc["action"] != old["action"]:
            continue
        lo, hi = span(inc)
        off = 0 if lo <= old["t"] <= hi else min(abs(old["t"] - lo), abs(old["t"] - hi))
        if off <= SLACK_S * SECOND and (best is None or off < best[0]):
            best = (off, i)
    return None if best is None else best[1]


def margin_text(inc: dict[str, Any]) -> str:
    m = inc.get("margin")
    if not m:
        return ""
    amount = f"{m.get('bound') + ' ' if m.get('bound') else ''}{m['value']:g} {m['unit']}"
    return f"{m['quantity']} {amount}" + (f" ± {m['uncertainty']:g}" if m.get("uncertainty") is not None else "")


def compare(old: list[dict[str, Any]], new: list[dict[str, Any]]) -> dict[str, Any]:
    went: dict[int, list[dict[str, Any]]] = {}
    changed, gone = [], []
    same = 0
    for inc in old:
        i = match(inc, new)
        if i is None:
            gone.append(inc)
            continue
        went.setdefault(i, []).append(inc)
        now = new[i]
        if now["verdict"] == inc["verdict"]:
            same += 1
        else:
            changed.append({"vehicle": inc["vehicle"], "t": inc["t"], "action": inc["action"],
                            "old": f"{inc['verdict']} ({inc.get('rule') or 'no rule'})",
                            "new": f"{now['verdict']} ({now.get('rule') or 'no rule'})", "new_id": now["id"],
                            "margin": margin_text(now), "why": now.get("why") or ""})
    merged = {i: olds for i, olds in went.items() if len(olds) > 1}
    found = [new[i] for i in range(len(new)) if i not in went]
    return {"old": len(old), "new": len(new), "same": same, "changed": changed, "gone": gone,
            "merged": [{"into": new[i]["id"], "vehicle": new[i]["vehicle"], "action": new[i]["action"],
                        "from": [o["id"] for o in olds], "verdicts": sorted({o["verdict"] for o in olds})}
                       for i, olds in sorted(merged.items())],
            "found": [{"id": n["id"], "vehicle": n["vehicle"], "action": n["action"], "verdict": n["verdict"],
                       "rule": n.get("rule"), "found_in": n.get("found_in"), "why": n.get("why") or ""}
                      for n in found]}


def clock(t: int) -> str:
    return datetime.fromtimestamp(t / SECOND, tz=timezone.utc).strftime("%H:%M:%S.%f")[:-5]


def show(result: dict[str, Any]) -> None:
    print(f"old incidents {result['old']}, new {result['new']}: {result['same']} old kept their verdict, "
          f"{len(result['changed'])} changed, {len(result['merged'])} acts now one incident where there were several, "
          f"{len(result['gone'])} gone, {len(result['found'])} found now")
    for c in result["changed"]:
        print(f"  changed: vehicle {c['vehicle']} {c['action']} at {clock(c['t'])}: {c['old']} -> {c['new']}"
              f" [{c['new_id']}]{'; ' + c['margin'] if c['margin'] else ''}; why: {c['why'][:300]}")
    for m in result["merged"]:
        print(f"  one act: vehicle {m['vehicle']} {m['action']}: {', '.join(m['from'])} -> {m['into']} "
              f"(old verdicts {', '.join(m['verdicts'])})")
    for g in result["gone"]:
        print(f"  gone: {g['id']} vehicle {g['vehicle']} {g['action']} ({g['verdict']}, {g.get('rule')})")
    kinds = Counter((f["action"], f["verdict"], f["found_in"]) for f in result["found"])
    for (action, verdict, where), n in sorted(kinds.items()):
        print(f"  found now: {n} x {action}, {verdict}, found in {where}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    with open(args.old, encoding="utf-8") as f_old, open(args.new, encoding="utf-8") as f_new:
        result = compare(json.load(f_old), json.load(f_new))
    if args.json:
        print(json.dumps(result, indent=1))
    else:
        show(result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
