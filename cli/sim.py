"""`gaps sim`: run the junction simulation on SUMO and publish what its road users, signals and
monitors record (DESIGN "Simulation"). Argument parsing and output only: the simulation is
sim_replay.simulation's, the publishing and recording sim_replay.outlets', the ingest ingest's."""
from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Optional

import typer

from cli.app import db_path, fail, writable_output
from cli.options import InsecureOption, JsonOption, ZenohConfigOption
from reasoner import format_seconds

def parse_duration(text: str) -> float:
    """`--duration` in world seconds, read by the one duration parser (reasoner.when)."""
    from reasoner import DurationError
    from reasoner import parse_duration as duration_ns
    try:
        return duration_ns(text) / 1e9
    except DurationError as exc:
        raise typer.BadParameter(str(exc)) from None


def parse_speed(text: str) -> float | None:
    """"max" (as fast as the simulation runs) or a factor of real time ("1", "10")."""
    if text.strip().lower() == "max":
        return None
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value > 0 or value != value:
        raise typer.BadParameter(f"{text!r} is not a speed: write max, or a factor of real time such as 1 or 10")
    return value


def parse_faults(text: str | None, names: tuple[str, ...]) -> dict[str, float]:
    """"misperceived_light=0.2,lost_event=0.01" as {name: rate}; rates from 0 to 1."""
    rates: dict[str, float] = {}
    for part in filter(None, (p.strip() for p in (text or "").split(","))):
        name, _, value = part.partition("=")
        name = name.strip().replace("-", "_")
        if name not in names:
            raise typer.BadParameter(f"unknown fault {name!r}: use {', '.join(names)} (each =RATE from 0 to 1)")
        try:
            rate = float(value)
        except ValueError:
            rate = -1.0
        if not 0.0 <= rate <= 1.0:
            raise typer.BadParameter(f"fault {name}: {value!r} is not a rate from 0 to 1")
        rates[name] = rate
    return rates


def sim(
    map_: str = typer.Option("paper", "--map", metavar="NAME|FILE",
                             help="A bundled map (paper, town), a SUMO network FILE.net.xml (left-hand traffic), "
                             "or a SUMO configuration FILE.sumocfg (its net-file and route-files)."),
    routes: list[Path] = typer.Option([], "--routes", metavar="FILE.rou.xml", help="SUMO routes: its vehicles, "
                                      "trips, flows and persons replace the drawn ones (repeatable; replaces "
                                      "a .sumocfg's route-files)."),
    monitors: Optional[Path] = typer.Option(None, "--monitors", help="Monitors file for a --map FILE "
                                            "(JSON: id, junction, x, y, heading_deg, range_m, fov_deg; default "
                                            "NAME.monitors.json beside NAME.net.xml, else no cameras)."),
    vehicles: int = typer.Option(40, "--vehicles", min=1, max=100_000, help="Vehicles that set off in the run."),
    duration: str = typer.Option("3m", "--duration", help="World time to simulate: 90s, 10m, 1h."),
    seed: int = typer.Option(0, "--seed", help="Same seed, same events."),
    rate: float = typer.Option(10.0, "--rate", min=0.5, max=10.0, help="entity.state and observations per second."),
    av_share: float = typer.Option(0.3, "--av-share", min=0.0, max=1.0, help="Share of cars driving themselves."),
    faults: Optional[str] = typer.Option(None, "--faults", metavar="NAME=RATE,…", help="Injected faults, each "
                                         "with a rate from 0 to 1: misperceived_light, missed_road_user, "
                                         "speed_error, lost_event, recorder_stops; several "
                                         "joined by commas (e.g. lost_event=0.01)."),
    run: str = typer.Option("sim-001", "--run", help="Run id."),
    record: Optional[Path] = typer.Option(None, "--record", help="Also record the events as MCAP."),
    truth: Optional[Path] = typer.Option(None, "--truth", help="Write the ground truth here (default: beside "
                                         "the recording or the store, RUN.truth.json)."),
    speed: str = typer.Option("max", "--speed", help="max, or a factor of real time (1: real time)."),
    listen: list[str] = typer.Option([], "--listen", help="Zenoh endpoint to listen on for an ingest (repeatable)."),
    connect: list[str] = typer.Option([], "--connect", help="Zenoh endpoint of a running `gaps serve` (repeatable)."),
    zenoh_file: Optional[Path] = ZenohConfigOption,
    insecure: bool = InsecureOption,
    db: Optional[Path] = typer.Option(None, "--db", help="Without --listen/--connect/--config: store into this file through "
                                      "an in-process ingest (default: $GAPS_DB or ./gaps.db)."),
    sign_keys: Optional[Path] = typer.Option(None, "--sign-keys", metavar="DIR", help="Sign every event with its "
                                             "source's Ed25519 key from DIR (made for sources that have none), and "
                                             "write DIR/public-keys.json."),
    json_out: bool = JsonOption,
) -> None:
    """Simulate the junctions on SUMO and publish every event over Zenoh.

    Automated vehicles ask the rulebook, human drivers follow their profiles, monitors watch.
    The events go into an ingest here (on --db), or to the endpoints given; --record keeps them
    as MCAP too; the ground truth is written beside. With --sign-keys each source signs its
    events; `gaps verify --keys DIR/public-keys.json` checks them."""
    from sim_replay import FaultRates, SimConfig, refuse_second_producer, with_files
    from store import GapsError, StoreFault

    names = tuple(f.name for f in dataclasses.fields(FaultRates))
    config = SimConfig(run=run, seed=seed, vehicles=vehicles, duration_s=parse_duration(duration), rate_hz=rate,
                       av_share=av_share, faults=FaultRates(**parse_faults(faults, names)))
    config = with_files(config, map_, tuple(routes), monitors)
    pace = parse_speed(speed)
    store_file = None if listen or connect or zenoh_file else db_path(db)
    truth_file = truth or (record or store_file or Path(f"{run}.mcap")).with_name(f"{run}.truth.json")
    for output in (record, truth_file):     # before the simulation: evidence is never an output
        writable_output(output, store_file)
    refuse_second_producer(run, store_file, truth_file)
    try:
        signer = _signer(sign_keys)
        wire = {"listen": listen, "connect": connect, "config_file": zenoh_file, "insecure": insecure}
        summary, sent, stored = _run(config, pace, record, wire, store_file, truth_file, signer)
        public_keys = str(signer.folder.write_public_keys()) if signer else None
    except StoreFault:
        raise           # SQLite could not read the store: said as every command says it (cli/app.py)
    except (GapsError, TimeoutError, OSError) as exc:
        fail(str(exc), getattr(exc, "exit_code", 2))     # 4 for a store a serve is writing, as README says
    out = {"run": run, "simulation": summary.to_json(), "published": sent.to_json(), "stored": stored,
           "truth": str(truth_file), "public_keys": public_keys}
    if json_out:
        typer.echo(json.dumps(out, indent=2))
        return
    _print(out, store_file)


def _signer(folder: Path | None):
    """The events' signer from a key folder (keys made for new sources), or None."""
    if folder is None:
        return None
    from store.keys import KeyFolder, Signer
    return Signer(KeyFolder(folder), create=True)


def _run(config, pace, record, wire, store_file, truth_file, signer=None):
    """Simulate and send; composition of the rooms' own calls only."""
    from cli.local_ingest import publish_through_zenoh
    from cli.progress import stderr_progress
    from sim_replay import Outlets, Simulation, refuse_if_held_otherwise

    with stderr_progress(f"simulating {config.run}") as bar:
        simulation = Simulation(config, (lambda done, total: bar(int(done), int(total))) if bar else None,
                                account=True)      # its truth is written: with SUMO's own account of who yielded
        stored = None
        if store_file is not None:
            stored, sent = publish_through_zenoh(store_file, simulation.batches(), record=record, speed=pace,
                                                 signer=signer)
        else:
            with Outlets(**wire, record=record, speed=pace, signer=signer) as outlets:
                checked = outlets.session is None
                for batch in simulation.batches():
                    if not checked and batch:     # one run, one producer: asked before the first put
                        outlets.await_ingest(batch[0])
                        refuse_if_held_otherwise(outlets.session, batch)
                        checked = True
                    outlets.put_all(batch)
            sent = outlets.summary()
    simulation.truth.write(truth_file, [store_file] if store_file is not None else [])
    return simulation.summary, sent, stored


def _print(out: dict, store_file: Path | None) -> None:
    s, sent = out["simulation"], out["published"]
    typer.echo(f"Simulated run {out['run']}: {format_seconds(s['world_s'], 3)} of world time in "
               f"{format_seconds(s['wall_s'])}; "
               f"{s['vehicles']} vehicle{'s' if s['vehicles'] != 1 else ''}, "
               f"{s['pedestrians']} pedestrian{'s' if s['pedestrians'] != 1 else ''}")
    typer.echo(f"  events {s['events']:,} ({s['lost_events']:,} lost on purpose), rulebook queries "
               f"{s['rulebook_queries']:,}, potential violations recorded by monitors {s['potential_violations']:,}, "
               f"acts in the ground truth {s['acts']:,}")
    if store_file is not None:
        st = out["stored"]
        typer.echo(f"  stored {st['stored']:,}, duplicates {st['duplicates']:,}, rejected {st['rejected']:,} → {store_file}")
    else:
        typer.echo(f"  published {sent['published']:,} events over Zenoh")
    if sent["recording"]:
        typer.echo(f"  recorded {sent['recorded']:,} events → {sent['recording']} ({sent['recording_bytes']:,} bytes)")
    typer.echo(f"  ground truth → {out['truth']}")
    if out["public_keys"]:
        typer.echo(f"  signed by each source; public keys → {out['public_keys']} (gaps verify --keys FILE)")
    if store_file is not None:
        typer.echo(f"Next: gaps incidents --db {store_file} --run {out['run']}")
