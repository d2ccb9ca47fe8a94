"""Who was in control of a vehicle at a moment, from its spawn and its ads.event history.

The store folds a vehicle's ads.event history into a status (`store.state.ads_status`): whether
the automated driving system is engaged and since which event, and any transition demand,
minimal risk manoeuvre or failure in progress. This module reads that status as the Automated
Vehicles Act 2024 does (see liability.le), and states it as the input sentences of liability.le.

Decisions made here (recorded in the closing note of issue 6 and in docs/reasoner.md):
- The parties are named by their role: `driver`, `user_in_charge`, `asde` (the authorised
  self-driving entity), `operator` (the no-user-in-charge operator); the record names no people.
- A vehicle has an ADS if its spawn says `driver: autonomous`, its automation level is 3 or more,
  or it has recorded any ads.event. SAE level 4-5 with `driver: autonomous` means no
  user-in-charge is needed (a no-user-in-charge operator answers); otherwise the person in the
  seat is the user-in-charge while the feature drives.
- A transition demand left unanswered for TRANSITION_DEMAND_S seconds has expired: the
  user-in-charge is then the driver (UN R157 para 5.4.4.1 gives the driver at least 10 s).
- With the feature not engaged (never activated, deactivated, or overridden by the driver), the
  human in the seat is the driver.
"""
from __future__ import annotations

from typing import Any

from ..vocabulary import (IS_DRIVING_ITSELF, IS_THE_AUTHORISED_SELF_DRIVING_ENTITY_FOR, IS_THE_DRIVER_OF,
                         IS_THE_NO_USER_IN_CHARGE_OPERATOR_OF, IS_THE_USER_IN_CHARGE_OF, TRANSITION_DEMAND_EXPIRED)

SECOND = 1_000_000_000
TRANSITION_DEMAND_S = 10

ROLE = {"driver": "driver", "user_in_charge": "user-in-charge", "asde": "authorised self-driving entity",
        "operator": "no-user-in-charge operator"}


def has_ads(spawn_body: dict, ads: dict | None) -> bool:
    level = spawn_body.get("automation_level")
    return (spawn_body.get("driver") == "autonomous" or ads is not None
            or (isinstance(level, int) and not isinstance(level, bool) and level >= 3))


def no_user_in_charge(spawn_body: dict) -> bool:
    level = spawn_body.get("automation_level")
    return (spawn_body.get("driver") == "autonomous" and isinstance(level, int)
            and not isinstance(level, bool) and level >= 4)


def control_at(record: dict | None, t: int) -> dict[str, Any]:
    """Who was in control at t, with the events that show it.

    in_control: "driver", "self-driving feature" or "user-in-charge" (after an expired transition
    demand); ads: whether the vehicle has an ADS, and its folded status."""
    record = record or {}
    spawn_body = (record.get("spawn") or {}).get("body") or {}
    ads = record.get("ads")
    equipped = has_ads(spawn_body, ads)
    engaged = bool(ads and ads["engaged"])
    demand = ads.get("transition_demand") if ads else None
    expired = bool(engaged and demand and t - demand["t"] >= TRANSITION_DEMAND_S * SECOND)
    nuic = equipped and no_user_in_charge(spawn_body)
    if not engaged:
        in_control = "driver"
    elif expired and not nuic:
        in_control = "user-in-charge"
    else:
        in_control = "self-driving feature"
    return {
        "in_control": in_control,
        "automated": equipped,
        "engaged": engaged,
        "user_in_charge": equipped and not nuic,
        "no_user_in_charge": nuic,
        "transition_demand": demand,
        "transition_demand_expired": expired,
        "since": ads.get("since") if ads else None,
        "minimal_risk_manoeuvre": ads.get("minimal_risk_manoeuvre") if ads else None,
        "failure": ads.get("failure") if ads else None,
        "last_ads_event": _cut(ads.get("last")) if ads else None,
    }


def _cut(piece: dict | None) -> dict | None:
    if not piece:
        return None
    return {"src": piece["src"], "seq": piece["seq"], "t": piece["t"], "event": piece["body"].get("event")}


def liability_facts(vehicle: str, control: dict[str, Any]) -> list[tuple[str, str]]:
    """The input sentences of liability.le for this vehicle at that moment (without the
    punishable violation, which the validator adds), each with what shows it: "spawn" (what the
    vehicle is), "since" (the ads.event that engaged or disengaged the feature, or the spawn if
    none did) or "transition_demand" (the demand left unanswered)."""
    since = "since" if control["since"] else "spawn"
    if not control["engaged"]:
        return [(IS_THE_DRIVER_OF.text("driver", vehicle), since)]
    facts = [(IS_DRIVING_ITSELF.text(vehicle), since),
             (IS_THE_AUTHORISED_SELF_DRIVING_ENTITY_FOR.text("asde", vehicle), "spawn")]
    if control["no_user_in_charge"]:
        facts.append((IS_THE_NO_USER_IN_CHARGE_OPERATOR_OF.text("operator", vehicle), "spawn"))
    else:
        facts.append((IS_THE_USER_IN_CHARGE_OF.text("user_in_charge", vehicle), "spawn"))
        if control["transition_demand_expired"]:
            facts.append((TRANSITION_DEMAND_EXPIRED.text(vehicle), "transition_demand"))
    return facts


def role(party: Any) -> str:
    """A liability.le party as DESIGN's `liable` value."""
    return ROLE.get(str(party), str(party))
