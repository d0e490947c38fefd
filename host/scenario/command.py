"""``mpy-fil scenario path/to/x.test.yaml``: the scenario's steps as they run, each with
its virtual time; a summary line (simulated and wall time); exit 0 when every step
passed, 1 when one failed (the step, its line, what was seen, the artefacts), 2 for a
file that cannot be run as written (one line, from the CLI)."""

import sys
from pathlib import Path

from host.scenario.runner import StepFailed
from host.scenario.scenario import ScenarioError, parse_time_us
from host.scenario.session import run_scenario

EXIT_OK, EXIT_FAILED = 0, 1


def add_parser(sub, folder_type, seed_type) -> None:
    """The subcommand's arguments (``host/cli.py`` calls this, then dispatches to :func:`cmd_scenario`)."""
    sc = sub.add_parser(
        "scenario", help="run a Wokwi automation scenario (*.test.yaml) against its rig, in virtual time"
    )
    sc.add_argument("scenario", metavar="SCENARIO", help="a scenario file; its rig: rig.toml in its folder or above")
    sc.add_argument(
        "--timeout",
        metavar="TIME",
        help="the run's timeout in simulated time (30s, 90000ms); default: the file's, or 30s as Wokwi's",
    )
    sc.add_argument("--seed", type=seed_type, default=0, help="seed of the plant's generator (default: 0)")
    sc.add_argument("--out", type=folder_type, help="trace folder (default: build/scenarios/<name> beside the rig)")
    sc.set_defaults(command=cmd_scenario, sub=sc)


def cmd_scenario(args) -> int:
    path = Path(args.scenario)
    if not path.is_file():
        raise ScenarioError(f"{path}: no such scenario file")
    timeout_us = parse_time_us(args.timeout, "--timeout") if args.timeout is not None else None
    if timeout_us is not None and timeout_us <= 0:
        raise ScenarioError("--timeout: expected a time above 0")
    try:
        outcome = run_scenario(path, out=args.out, seed=args.seed, timeout_us=timeout_us, echo=print)
    except StepFailed as e:
        sys.stdout.flush()
        print(f"FAIL {e}", file=sys.stderr)
        return EXIT_FAILED
    sim_s = outcome.t_end_us / 1e6
    print(
        f"pass: {outcome.scenario.name}: {len(outcome.results)} steps, {sim_s:g} simulated s in "
        f"{outcome.wall_s:.2f} wall s ({sim_s / max(outcome.wall_s, 1e-9):.1f}x real time); "
        f"trace folder: {outcome.artefacts}"
    )
    return EXIT_OK
