"""``mpy-fil``: ad-hoc runs, replays and plots from the command line.

    mpy-fil run --app rover --world long-room --seed 3 --duration 60
    mpy-fil run path/to/rig.toml --duration 20
    mpy-fil check path/to/rig.toml
    mpy-fil run path/to/wokwi-project/     (its diagram.json and main.py: docs/wokwi.md)
    mpy-fil import-wokwi path/to/wokwi-project/
    mpy-fil replay build/runs/rover-long-room-seed3
    mpy-fil plot build/runs/rover-long-room-seed3
    mpy-fil campaign campaigns/duct_snag.toml --seeds 20 --workers 2 [--shrink]
    mpy-fil shrink build/campaign/duct_snag/runs/tether-snags/one-right-branch/8
    mpy-fil diff build/runs/old build/runs/new --max-pos-m 0.05
    mpy-fil mcp          (live rigs as Model Context Protocol tools over stdio: docs/live.md)
    mpy-fil setup        (the MicroPython interpreter, once per user: docs/ci.md)
    mpy-fil docs ci      (docs/NAME.md, as every message names a page: mpy-fil docs NAME)
    mpy-fil --version

A bad argument is reported by name with exit code 2; a run that fails (firmware
exception, watchdog) prints the harness's message and exits with 1; a replay whose
outputs differ from the recording exits with 1. This is the only layer that prints
or exits.
"""

from host.core import stop_signals  # (first: a stop signal during the imports below, a second's, is named)

# isort: split

import argparse
import ast
import contextlib
import math
import os
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path

from host.artefacts.folder import HEADER
from host.core import safefs
from host.core.docs import add_parser as _docs_parser
from host.core.errors import ConfigError, HarnessError
from host.core.paths import FIRMWARE, output_root
from host.core.printable import printable
from host.report.progress import MissionProgress
from host.report.table import format_table
from host.rig.config import arguments
from host.rig.config.apps import apps, get_app
from host.rig.scan import boards as pin_maps
from sim_plant import names

CONSOLE_LINES = 10  # the console's last lines a run shows (all of them in console.log)
EXIT_FAILED = 1
EXIT_USAGE = 2
MAX_DURATION_S = arguments.MAX_RUN_S  # the rig's own bounds: ten simulated days in one run
MAX_SEED = arguments.SEED_MAX  # the plant's generator takes a 32-bit seed
MAX_WORKERS = 256  # a campaign's local processes (each run starts an interpreter too)


def main(argv=None) -> int:
    """Every command: SIGINT (Ctrl-C), SIGTERM and SIGHUP stop it as Ctrl-C does, each
    reported as itself with exit code 128 + its number, whenever it comes (parsing,
    running, writing, plotting); the handlers before are put back at the end."""
    with _stop_on_signals():
        return _main(argv)


def _main(argv) -> int:
    prog = "mpy-fil"
    try:
        args = build_parser().parse_args(argv)
        prog = args.sub.prog
        return args.command(args)
    except ConfigError as e:  # names its file and field: one line, no usage text
        print(f"{prog}: error: {printable(e)}", file=sys.stderr)
        return EXIT_USAGE
    except HarnessError as e:
        print(f"{prog}: {type(e).__name__}: {printable(e)}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt as e:  # (a stop signal: Stopped names it; a bare one is Ctrl-C)
        signum = getattr(e, "signum", signal.SIGINT)
        print(f"{prog}: stopped by {signal.Signals(signum).name}", file=sys.stderr)
        return 128 + signum
    except BrokenPipeError:  # (piped into head: the reader had enough)
        sys.stdout = open(os.devnull, "w")
        return 0
    except OSError as e:  # (a plot on a full disk): the file named, no traceback
        print(f"{prog}: cannot write {e.filename or 'a file'}: {e.strerror or e}", file=sys.stderr)
        return EXIT_FAILED


class OneLineParser(argparse.ArgumentParser):
    """A parser whose errors are one line on stderr and exit code 2 (the usage text is
    one ``--help`` away), as every other refusal of the command line is."""

    def error(self, message: str):
        shown = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)  # (an argument's \r, \n)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {shown}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="mpy-fil",
        description="Run MicroPython robot firmware in the loop, replay a recorded trace, or plot one.",
        epilog="docs/NAME.md, as help and messages name a page: `mpy-fil docs NAME` prints it "
        "(`mpy-fil docs` lists them).",
    )
    parser.add_argument("--version", action="version", version=f"mpy-fil {package_version()}")
    sub = parser.add_subparsers(title="commands", metavar="COMMAND", required=True, parser_class=OneLineParser)

    run = sub.add_parser("run", help="run an app in a world for a duration; writes a trace folder")
    run.add_argument(
        "rig", nargs="?", metavar="RIG", help="a rig file (docs/rig-file.md) or a Wokwi project folder; default: --app"
    )
    run.add_argument("--app", default="rover", choices=sorted(apps()), help="one of our apps (default: rover)")
    run.add_argument("--board", help="board pin map (default: the app's own; see firmware/boards)")
    run.add_argument("--world", help="named world of the app (default: its first)")
    run.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        type=_param,
        help="a plant option, e.g. room_w_m=6.5 (repeatable; overrides the world's)",
    )
    run.add_argument(
        "--seed", type=_seed, default=0, help=f"seed of the plant's generator, 0 to {MAX_SEED} (default: 0)"
    )
    run.add_argument(
        "--duration",
        type=_duration_s,
        default=30.0,
        metavar="SECONDS",
        help=f"virtual seconds, at most {MAX_DURATION_S} (10 simulated days; default 30)",
    )
    run.add_argument(  # (the campaign's word for it)
        "--seconds", dest="duration", type=_duration_s, default=argparse.SUPPRESS, help="the same as --duration"
    )
    run.add_argument("--mode", choices=("lockstep", "realtime"), default="lockstep", help="clock (default: lockstep)")
    run.add_argument(
        "--out",
        type=_folder,
        help="trace folder (default: build/runs/<app>-<world>-seed<N>, beside your rig file)",
    )
    run.add_argument("--no-plots", action="store_true", help="write the trace folder only")
    run.add_argument(
        "--allow-exit",
        action="store_true",
        help="a firmware that ends (returns, sys.exit) ends the run without an error (or [firmware] allow_exit)",
    )
    run.add_argument(
        "--coverage", action="store_true", help="the firmware's line and branch coverage (docs/coverage.md)"
    )
    run.add_argument(
        "--interactive",
        action="store_true",
        help="Ctrl-C pauses the run into a prompt (look, poke, go on: docs/live.md) instead of stopping it",
    )
    run.add_argument(
        "--break-at",
        metavar="WHEN",
        help="pause into the prompt at a virtual instant (2.5s, 300ms) or a console line (a regular expression)",
    )
    run.set_defaults(command=cmd_run, sub=run)

    check = sub.add_parser("check", help="check a rig file without running it; list the plant's signals")
    check.add_argument("rig", metavar="RIG", help="a rig file (docs/rig-file.md) or one of our apps")
    check.add_argument("--strict", action="store_true", help="exit 1 when the code's pins and the wiring differ")
    check.add_argument("-v", "--verbose", action="store_true", help="list the pin expressions only a run can tell")
    check.set_defaults(command=cmd_check, sub=check)

    init = sub.add_parser("init", help="write a commented starting rig file for a firmware folder")
    init.add_argument("folder", metavar="DIR", type=_folder, help="the firmware folder (its main.py)")
    init.add_argument("--kit", metavar="NAME", help="a robot kit's rig file and a test for it (mpy-fil kits)")
    init.set_defaults(command=cmd_init, sub=init)

    mig = sub.add_parser("migrate", help="write a 0.1 rig file ([plant] kind) as a body and parts")
    mig.add_argument("rig", metavar="RIG", type=Path, help="the 0.1 rig file")
    where = mig.add_mutually_exclusive_group()
    where.add_argument(
        "-o", "--out", type=Path, help="the file to write, in RIG's folder (default: <RIG>.migrated.toml)"
    )
    where.add_argument("--in-place", action="store_true", help="replace RIG itself")
    mig.set_defaults(command=cmd_migrate, sub=mig)

    kits_ = sub.add_parser("kits", help="the robot kits init --kit knows, with their sources")
    kits_.set_defaults(command=cmd_kits, sub=kits_)

    wok = sub.add_parser("import-wokwi", help="write the rig.toml of a Wokwi project folder (its diagram.json)")
    wok.add_argument("folder", metavar="DIR", type=_folder, help="the Wokwi project (diagram.json, main.py)")
    wok.add_argument("--force", action="store_true", help="overwrite its rig.toml")
    wok.set_defaults(command=cmd_import_wokwi, sub=wok)

    lst = sub.add_parser("list", help="our apps, boards, and the catalogue's bodies and parts: options and signals")
    lst.set_defaults(command=cmd_list, sub=lst)

    prt = sub.add_parser("parts", help="the catalogue's pages (ours, installed packages', a rig file's own entries)")
    prt.add_argument("kinds", nargs="*", metavar="KIND", help="only these entries (all when none)")
    prt.add_argument("--rig", metavar="RIG", help="a rig file: its [plant] catalogue's entries too")
    prt.set_defaults(command=cmd_parts, sub=prt)

    rep = sub.add_parser("replay", help="drive the firmware with a trace's sensor stream; compare its outputs")
    rep.add_argument(
        "trace",
        metavar="TRACE",
        type=_trace_or_set_folder,
        help="trace folder of a lockstep run (or a set's run folder)",
    )
    rep.add_argument("--out", type=_folder, help="the replay's own trace folder (default: TRACE/replay)")
    rep.add_argument("--app", metavar="RIG", help="run this rig file or app of ours (not the one TRACE names)")
    rep.add_argument("--firmware", metavar="DIR", type=_folder, help="run the firmware in this folder (the board's /)")
    rep.add_argument(
        "--trust-folder", action="store_true", help="run the rig file or firmware folder TRACE's header names"
    )
    rep.add_argument(
        "--ignore-manifest", action="store_true", help="replay even where TRACE's manifest.json differs from this run"
    )
    rep.set_defaults(command=cmd_replay, sub=rep)

    plot = sub.add_parser("plot", help="write a trace folder's plots (PNG)")
    plot.add_argument("trace", metavar="TRACE", type=_trace_folder, help="trace folder")
    plot.add_argument("--out", type=_folder, help="folder for the PNG files (default: TRACE/plots)")
    plot.set_defaults(command=cmd_plot, sub=plot)
    _campaign_parser(sub)
    from host.scenario.command import add_parser as _scenario_parser  # (Wokwi automation scenarios)

    _scenario_parser(sub, _folder, _seed)
    _testing_parsers(sub)
    _mcp_parser(sub)

    setup = sub.add_parser("setup", help="get the MicroPython interpreter: $MICROPYTHON, PATH, or built once per user")
    setup.add_argument(
        "--micropython",
        metavar="VERSION",
        help="the MicroPython version to get (default 1.25; several live side by side: docs/versions.md)",
    )
    setup.add_argument(
        "--source",
        metavar="DIR",
        help="MicroPython's own source (a clone) for a version Debian does not carry ($MICROPYTHON_SOURCE)",
    )
    setup.set_defaults(command=cmd_setup, sub=setup)
    _docs_parser(sub)  # mpy-fil docs [TOPIC]: the pages the package carries (host/core/docs.py)
    return parser


def package_version() -> str:
    """The installed package's version (pyproject.toml's)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("mpy-fil")
    except PackageNotFoundError:  # (run from a checkout that was never installed)
        return "0+unknown"


def _campaign_parser(sub) -> None:
    camp = sub.add_parser("campaign", help="a rig over seeds x fault sets x worlds, in parallel; its report")
    camp.add_argument("rig", nargs="?", metavar="RIG", help="a campaign scenario file, a rig file or one of our apps")
    camp.add_argument("--seeds", type=_count, help="how many seeds (default: the scenario's, or 10)")
    camp.add_argument("--first-seed", type=_seed, help="the first seed (default 1)")
    camp.add_argument("--faults", metavar="FILE", help="a file of [[faults]] or [[faultsets]]")
    camp.add_argument("--worlds", type=lambda s: s.split(","), help="worlds, comma-separated (default: the first)")
    camp.add_argument("--seconds", type=_duration_s, help="simulated seconds per run at most")
    camp.add_argument("--timeout", type=_duration_s, dest="timeout_s", help="wall seconds per run before it is hung")
    camp.add_argument(
        "--workers", type=_workers, default=os.cpu_count() or 1, help=f"local processes, at most {MAX_WORKERS}"
    )
    camp.add_argument("--scheduler", metavar="ADDRESS", type=_scheduler, help="a Dask scheduler, tcp://HOST:PORT")
    camp.add_argument("--out", type=_folder, help="results and report (default: build/campaign/<name>)")
    camp.add_argument("--replay", metavar="KEY", help="run faultset/world/seed of the campaign in --out again, traced")
    camp.add_argument("--shrink", action="store_true", help="then shrink each distinct failure (docs/testing-tools.md)")
    camp.set_defaults(command=cmd_campaign, sub=camp)


def _mcp_parser(sub) -> None:
    """``mpy-fil mcp``: live rigs as Model Context Protocol tools over stdio (docs/live.md)."""
    mcp = sub.add_parser("mcp", help="serve live rigs as Model Context Protocol tools over stdio (docs/live.md)")
    mcp.add_argument("--max-rigs", type=_count, default=1, help="rigs open at once (default 1)")
    mcp.add_argument(
        "--max-run-s", type=_duration_s, default=60.0, help="simulated seconds one call may run (default 60)"
    )
    mcp.add_argument(
        "--max-wall-s",
        type=_duration_s,
        default=300.0,
        help="wall seconds of all one rig's calls (default 300)",
    )
    mcp.add_argument("--out", type=_folder, help="trace folders of rigs started to record (default: a temporary one)")
    mcp.set_defaults(command=cmd_mcp, sub=mcp)


def cmd_mcp(args) -> int:
    from host.live.mcpserver import Limits, serve  # (the mcp SDK: imported for this command only)

    serve(Limits(args.max_rigs, args.max_run_s, args.max_wall_s), args.out)
    return 0


def _testing_parsers(sub) -> None:
    """``shrink`` and ``diff`` (docs/testing-tools.md); their bodies are in host/shrink, host/diff."""
    shr = sub.add_parser("shrink", help="shrink a failing run to a minimal one that fails the same way")
    shr.add_argument("run", metavar="RUN", help="a trace folder, or a campaign's run: CAMPAIGN/runs/KEY")
    shr.add_argument("--out", type=_folder, help="the minimal run's folder (default: build/shrink/<run>)")
    shr.add_argument("--workers", type=_workers, default=os.cpu_count() or 1, help="runs at once (default: the cores)")
    shr.add_argument("--resolution", type=_duration_s, metavar="SECONDS", help="windows and duration to this")
    shr.add_argument("--app", metavar="RIG", help="run this rig file or app (a trace folder's run)")
    shr.add_argument("--trust-folder", action="store_true", help="run the rig file a trace folder's header names")
    shrink = f"{__package__}.shrink.command"  # (host, or mpy_fil.host installed: setup.py)
    shr.set_defaults(command=lambda args: _say_command(shrink, "shrink_command", args), sub=shr)

    diff = sub.add_parser("diff", help="compare two trace folders: trajectories, outputs, budgets")
    where = "trace folder, or a set of boards' run folder (board by board)"
    diff.add_argument("a", metavar="A", type=_trace_or_set_folder, help=f"{where} (the reference)")
    diff.add_argument("b", metavar="B", type=_trace_or_set_folder, help=f"{where} (compared with A)")
    diff.add_argument("--out", type=_folder, help="folder for the plot (default: B/diff)")
    diff.add_argument("--max-pos-m", type=float, default=0.0, help="largest position deviation allowed (default 0)")
    diff.add_argument("--max-rms-m", type=float, default=0.0, help="largest RMS position deviation allowed (default 0)")
    diff.add_argument("--fail-on-output", action="store_true", help="differ when any output diverges")
    diff.add_argument("--max-p99-change-us", type=float, help="largest change of a budget's p99 allowed")
    diff.add_argument("--max-misses-change", type=int, help="largest rise of a budget's misses allowed")
    diff.set_defaults(command=lambda args: _say_command(f"{__package__}.diff.command", "diff_command", args), sub=diff)


def _say_command(module: str, name: str, args) -> int:
    """Run a command whose body lives in its own module, printing what it says."""
    import importlib

    return getattr(importlib.import_module(module), name)(args, say=lambda text: print(printable(text), flush=True))


def _workers(text: str) -> int:
    value = _count(text)
    if value > MAX_WORKERS:
        raise argparse.ArgumentTypeError(f"expected at most {MAX_WORKERS} local processes, got {value}")
    return value


def _scheduler(text: str) -> str:
    from host.campaign.runner import scheduler_address

    try:
        return scheduler_address(text)
    except ConfigError as e:
        raise argparse.ArgumentTypeError(str(e).removeprefix(f"--scheduler {text!r}: ")) from None


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected 1 or more, got {value}")
    return value


# -- argument types: each error names its argument through argparse ---------------------


def _duration_s(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not value > 0 or not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a positive number of seconds, got {text!r}")
    if value > MAX_DURATION_S:
        raise argparse.ArgumentTypeError(f"expected at most {MAX_DURATION_S} seconds (10 simulated days), got {text!r}")
    if round(value * 1e6) < 1:
        raise argparse.ArgumentTypeError(f"expected at least 0.000001 seconds (the clock's 1 us), got {text!r}")
    return value


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number from 0 to {MAX_SEED}, got {text!r}") from None
    if not 0 <= value <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"expected a whole number from 0 to {MAX_SEED}, got {text!r}")
    return value


def _folder(text: str) -> Path:
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a folder, got an empty name")
    return Path(text)


def _param(text: str) -> tuple[str, object]:
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        parsed = ast.literal_eval(value)
    except (ValueError, SyntaxError, MemoryError, RecursionError):
        parsed = value
        try:  # nan, inf: numbers literal_eval does not read
            parsed = float(value)
        except ValueError:
            pass
    if not _finite(parsed):
        raise argparse.ArgumentTypeError(f"{name.strip()}: expected finite numbers, got {value!r}")
    return name.strip(), parsed


def _finite(value) -> bool:
    if isinstance(value, (list, tuple, set)):
        return all(_finite(v) for v in value)
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    if isinstance(value, complex):
        return math.isfinite(value.real) and math.isfinite(value.imag)
    return not isinstance(value, float) or math.isfinite(value)


def _writable(sub, argument: str, folder: Path, inputs: dict | None = None, owned=None, base=None) -> Path:
    """``folder``, made if need be, as its real path (:func:`host.core.safefs.output_folder`:
    never one of ``inputs``, around or inside one but for its ``owned`` sub-folder, no link
    where it is made below ``base``); an argument error naming it if it cannot be written."""
    try:
        what = f"argument {argument}:" if base is None else ""  # (a default below base: not an argument's)
        real = safefs.output_folder(folder, what=what, inputs=inputs, owned=owned, base=base)
        with tempfile.TemporaryFile(dir=real):
            pass
    except OSError as e:
        sub.error(f"argument {argument}: cannot write to the folder {folder} ({e.strerror or e})")
    return real


def _trace_folder(text: str) -> Path:
    path = Path(text)
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"no trace folder at {text}")
    if not (path / HEADER).is_file():
        raise argparse.ArgumentTypeError(f"{text} is not a trace folder (no {HEADER})")
    return path


def _trace_or_set_folder(text: str) -> Path:
    """A trace folder, or a set of boards' run folder (a trace folder a board: ``diff``)."""
    from host.artefacts.folder import set_boards

    path = Path(text)
    if path.is_dir() and not (path / HEADER).is_file() and set_boards(path):
        return path
    return _trace_folder(text)


# -- commands ----------------------------------------------------------------------------


def cmd_run(args) -> int:
    from host.rig.config.boardfile import names_boards

    if args.rig and names_boards(args.rig):  # several boards (docs/multi-board.md)
        return _run_boards(args)
    return _run_one(args)


def _run_one(args) -> int:
    from host.link.transport import busy_poll_wanted
    from host.rig import Recording, Rig, RigSpec
    from host.rig.loop.spec import PlantOptionsError

    sub = args.sub
    app = get_app(args.rig) if args.rig else apps()[args.app]
    board = args.board or app.default_board
    known_boards = tuple(dict.fromkeys((app.default_board, *app.board.also)))
    if app.board.pins is None and not app.board.also:  # an app that names no boards runs on any of ours
        known_boards = tuple(pin_maps.known_boards())
    if board not in known_boards:
        known = names.unknown(board, known_boards, what="known")
        sub.error(f"argument --board: unknown board {board!r} for app {app.name} {known}")
    world = args.world or next(iter(app.worlds))
    if world not in app.worlds:
        known = names.unknown(world, app.worlds, what="known")
        sub.error(f"argument --world: unknown world {world!r} for app {app.name} {known}")
    if args.param:  # checked against the rig's own declarations (the body's and parts' options)
        try:
            app.make_plant(**dict(args.param))
        except (TypeError, ValueError, ArithmeticError) as e:
            sub.error(f"argument --param: {app.name}'s plant rejects it: {e}")
    root = output_root(app.rig_file)
    out = _writable(
        sub,
        "--out",
        args.out or root / "runs" / f"{app.name}-{world}-seed{args.seed}",
        inputs={"the firmware folder": app.path},
        owned={"the firmware folder": root},  # (build/ beside a rig file in its firmware folder)
        base=None if args.out else root.parent,
    )
    show = _progress(f"{app.name} in {world}, seed {args.seed}")
    spec = RigSpec(
        args.rig or args.app,
        board=board,
        world=world,
        seed=args.seed,
        options=dict(args.param),
        mode=args.mode,
        allow_exit=args.allow_exit,
        busy_poll=busy_poll_wanted(),
    )
    coverage = _coverage_file(out, app.interpreter.mpy_version) if args.coverage else None
    live = args.interactive or args.break_at is not None
    breaks = _break_at(args.break_at)
    recording = Recording(trace=True, record=True, artefacts=out, progress=None if live else show, coverage=coverage)
    try:
        runner = _interactive(spec, recording) if live else Rig(spec, recording)
    except PlantOptionsError as e:
        sub.error(f"argument --param: {e}")
    try:
        with runner:  # (main stops it at a signal, as at Ctrl-C)
            if live:
                _serve_interactive(runner, round(args.duration * 1e6), *breaks)
            else:
                runner.run_for(args.duration)
    except KeyboardInterrupt:
        print(f"\ntrace folder: {out} (partial: stopped at t={runner.t_us / 1e6:g} s)")
        raise
    finally:
        _progress_done(show)
    rig = runner.rig if live else runner
    _show_console(rig.console, out)
    for t_us, text in rig.bus_trace.notes:  # (a poll that never ends, a chip's note: also in console.log)
        print(printable(f"note at virtual t={t_us / 1e6:.6f} s: {text}"))
    if rig.console_log.dropped_bytes:
        log = rig.console_log
        dropped = f"{log.dropped_bytes} bytes in {log.dropped_lines} lines dropped"
        print(f"console.log capped at {log.max_bytes} bytes: {dropped}")
    truth = rig.truth()
    pose = ", ".join(f"{k} {truth[k]:.3f}" for k in ("x_m", "y_m", "theta_rad") if k in truth)
    print(f"ground truth at {rig.t_us / 1e6:g} s: {pose}; contacts: {len(truth.get('contacts', []))}")
    rows = rig.budget_rows()  # (a budget that measured nothing shows a count of 0)
    if rows:
        print(format_table(rows))
    if not args.no_plots:
        try:
            print("plots: drawing them ...", flush=True)
            from host.report.plots import plot_trace

            plot_trace(out)
        except KeyboardInterrupt:  # (the trace folder is whole: only plots are missing)
            print(f"plots: stopped; the trace folder {out} is whole (mpy-fil plot {out} draws them)")
            raise
    _list_files(out)
    if coverage is not None:
        from host.coverage.session import run_summary

        print(run_summary(coverage))
    return 0


def _run_boards(args) -> int:
    """``mpy-fil run`` of a rig file with several boards: each board's trace folder in the
    run's folder under its name, each board's console and budgets shown."""
    from host.rig.config.boardfile import load_boards
    from host.rig.loop.boardset import BoardSet

    sub = args.sub
    given = {"--board": args.board}
    given |= {"--mode": args.mode != "lockstep"}
    given |= {"--interactive": args.interactive, "--break-at": args.break_at is not None}
    for option in (option for option, value in given.items() if value):
        sub.error(f"argument {option}: not for a rig file with several boards (docs/multi-board.md)")
    boards = load_boards(args.rig)
    first = next(iter(boards.firmware().values()))
    if args.world is not None and args.world not in first.worlds:
        known = names.unknown(args.world, first.worlds, what="known")
        sub.error(f"argument --world: unknown world {args.world!r} for {boards.name} {known}")
    world = args.world if args.world is not None else next(iter(first.worlds))
    if args.param:  # checked against the plant's own declarations, as a one-board rig's
        try:
            boards.make_plant(**{**first.worlds[world], **dict(args.param)})
        except (TypeError, ValueError, ArithmeticError, ConfigError) as e:
            sub.error(f"argument --param: {boards.name}'s plant rejects it: {e}")
    root = output_root(boards.rig_file)
    out = _writable(
        sub,
        "--out",
        args.out or root / "runs" / f"{boards.name}-{world}-seed{args.seed}",
        inputs={f"board {name}'s firmware folder": app.path for name, app in boards.firmware().items()},
        owned={f"board {name}'s firmware folder": root for name in boards.firmware()},
        base=None if args.out else root.parent,
    )
    options = {"world": world, "plant_options": dict(args.param or {}), "allow_exit": args.allow_exit}
    # --coverage: each board's firmware measured into its own folder's coverage/ (docs/coverage.md)
    measured = boards.firmware().items() if args.coverage else ()
    coverage = {name: _coverage_file(out / name, app.interpreter.mpy_version) for name, app in measured}
    options["coverage"] = coverage.get if coverage else None
    with BoardSet(boards, seed=args.seed, trace=True, record=True, artefacts=out, **options) as run:
        run.run_for(args.duration)
    for name, rig in run.rigs.items():
        print(f"board {name}:" if name in boards.firmware() else f"host program {name}:")
        _show_console(rig.console, out / name)
        rows = rig.budget_rows() if name in boards.firmware() else None
        if rows:
            print(format_table(rows))
        if name in coverage:
            from host.coverage.session import run_summary

            print(f"board {name}'s {run_summary(coverage[name])}")
    if run.budgets:
        print("budgets across boards:")
        print(format_table([b.stats() for b in run.budgets.values()]))
    truth = run.truth()
    pose = ", ".join(f"{k} {truth[k]:.3f}" for k in ("x_m", "y_m", "theta_rad") if k in truth)
    print(f"ground truth at {run.t_us / 1e6:g} s: {pose or 'no pose'}; contacts: {len(truth.get('contacts', []))}")
    if not args.no_plots:
        from host.report.plots import plot_trace

        print("plots: drawing them ...", flush=True)
        for name in boards.firmware():
            plot_trace(out / name)
    _list_files(out)
    return 0


def _interactive(spec, recording):
    from host.live import LiveRig

    return LiveRig(spec, recording)


def _break_at(text: str | None) -> tuple:
    """``--break-at``: (an instant in µs, None) for a time with its unit, else (None, a
    console line's regular expression)."""
    import re

    from host.scenario.scenario import ScenarioError, parse_time_us

    if text is None:
        return None, None
    try:
        return parse_time_us(text, "--break-at"), None
    except ScenarioError:
        pass
    try:
        return None, re.compile(text)
    except re.error as e:
        raise ConfigError(f"--break-at: neither a time (2.5s, 300ms) nor a regular expression: {e}") from None


def _serve_interactive(live, end_us: int, break_us, break_console) -> None:
    """``--interactive``, ``--break-at``: the run pauses into a prompt (host/live/prompt.py)."""
    from host.live.prompt import Interactive

    def ask(prompt: str):
        try:
            return input(prompt)
        except EOFError:
            return None

    say = lambda text: print(printable(text), flush=True)  # noqa: E731
    say(f"running to t={end_us / 1e6:g} s; Ctrl-C pauses it into a prompt (docs/live.md)")
    Interactive(live, end_us, say, ask, break_us, break_console).run()


def _coverage_file(out: Path, version: str | None) -> Path:
    from host.coverage.session import prepare_run

    return prepare_run(out, version)


def _show_console(text: str, out: Path) -> None:
    """The firmware's last console lines (all of them in the trace folder's console.log)."""
    lines = text.splitlines()
    if not lines:
        print("console: the firmware printed nothing")
        return
    shown = lines[-CONSOLE_LINES:]
    print(f"console (the last {len(shown)} lines; all in {out / 'console.log'}):")
    for line in shown:
        print(f"  | {printable(line)}")


def _list_files(out: Path) -> None:
    """Every file the run wrote, with its size: the trace, the plots, the GIF."""
    files = sorted(p for p in out.rglob("*") if p.is_file())
    print(f"trace folder: {out} ({len(files)} files)")
    for path in files:
        print(f"  {path.relative_to(out)}  {_size(path.stat().st_size)}")


def _size(n_bytes: int) -> str:
    for unit in ("B", "kB", "MB"):
        if n_bytes < 1000 or unit == "MB":
            return f"{n_bytes:.0f} {unit}" if unit == "B" else f"{n_bytes:.1f} {unit}"
        n_bytes /= 1000
    return ""


@contextlib.contextmanager
def _stop_on_signals():
    """While the block runs, SIGINT, SIGTERM and SIGHUP stop the command as Ctrl-C does
    (a run's trace folder written, marked partial; a campaign's pool stopped, its results
    kept), raising :class:`Stopped` with the signal; a second signal while that is done is
    ignored. The handlers before are put back after it."""
    if threading.current_thread() is not threading.main_thread():  # (only the main thread takes signals)
        yield
        return
    previous = stop_signals.install()  # (a signal ignored from the start, as by nohup, stays ignored)
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def cmd_check(args) -> int:
    from host.rig.config.boardfile import load_boards, names_boards

    if names_boards(args.rig):  # several boards (docs/multi-board.md): each checked as one board
        boards = load_boards(args.rig)
        print(f"{boards.rig_file}: {len(boards.apps)} boards on one plant: {', '.join(boards.apps)}")
        firmware = boards.firmware()
        wired = {signal for app in firmware.values() for signal in app.wiring.values()}
        for name in boards.apps.keys() - firmware.keys():
            print(f"[[boards]] {name}: a host program, {boards.apps[name].path} ({boards.apps[name].function})")
        return max(_check_app(app, args, f"[[boards]] {name}", wired) for name, app in firmware.items())
    return _check_app(get_app(args.rig), args)


def _check_app(app, args, label: str = "", wired_elsewhere: set = frozenset()) -> int:
    """One board's rig checked and described (``label``, ``wired_elsewhere``: a board of a set's)."""
    from host.rig.loop.spec import RigSpec, build_plant

    plant, _ = build_plant(RigSpec(app), app)
    on_buses = sorted({d.bus for d in plant.bus_devices()})
    if app.wiring:
        print(f"{label or app.rig_file or app.name}: ok")
    elif on_buses:  # (chips on buses or lines need no wiring: the rig puts them there by name)
        print(f"{app.rig_file or app.name}: ok (0 pins wired; its parts are on {', '.join(on_buses)})")
    else:  # (it loads, but the firmware and the plant are not connected)
        print(f"{app.rig_file or app.name}: loads, but 0 pins are wired: the firmware reads nothing from the plant")
        print("  and drives nothing of it; wire its pins to the plant's signals in [wiring] (docs/rig-file.md)")
    print(f"  firmware: {app.path} (entry {app.code.entry})")
    folders = app.firmware_folders(app.board_files(app.default_board)[0])
    print(f"  path: {' : '.join(str(f) for f in folders)}")
    print(
        f"  board: {app.default_board}"
        + (f" (also {', '.join(app.board.also[1:])})" if len(app.board.also) > 1 else "")
    )
    print(f"  plant: {plant.summary}")
    print(f"    inputs (the firmware drives): {', '.join(f'{n} ({k})' for n, k in plant.inputs.items())}")
    print(f"    outputs (the firmware reads): {', '.join(f'{n} ({k})' for n, k in plant.outputs.items())}")
    wired = set(app.wiring.values()) | plant.driven_inputs() | wired_elsewhere  # (a PWM expander's)
    loose = [n for n in [*plant.inputs, *plant.outputs] if n not in wired]
    print(
        f"  wiring: {len(app.wiring)} pins" + (f"; plant signals wired to no pin: {', '.join(loose)}" if loose else "")
    )
    for budget in app.make_budgets(plant):
        print(f"  budget {budget.name}: {budget.limit_text()}  {budget.description}")
    print(f"  worlds: {', '.join(app.worlds)}")
    return _check_pins(app, args, plant)


def _check_pins(app, args, plant=None) -> int:
    """The code's pins (and buses) against the wiring: warnings on stderr (exit 1 with --strict)."""
    from host.rig.scan.pincheck import check_pins

    pins = check_pins(app, plant)
    print(f"  pins the code uses: {pins.checked} compared with the wiring, {len(pins.unchecked)} not checked")
    for line in pins.notes:
        print(f"    {printable(line)}")
    for line in pins.unchecked if args.verbose else ():
        print(f"    not checked (computed at run time): {printable(line)}")
    for line in pins.warnings:
        print(printable(line), file=sys.stderr)
    return EXIT_FAILED if pins.warnings and args.strict else 0


def cmd_kits(args) -> int:
    from host.kits import kits

    for name, kit in kits().items():
        print(f"{name:<14} {kit.title}\n  board: {kit.board}; library: {kit.library}")
        for what, where in kit.sources:
            print(f"  {what}: {where}")
    print("mpy-fil init --kit NAME DIR writes DIR/rig.toml and DIR/test_NAME.py (docs/kits.md)")
    return 0


def _init_kit(args) -> int:
    from host.kits import kit, write

    folder = args.folder
    try:
        chosen = kit(args.kit)
    except ConfigError as e:
        args.sub.error(f"argument --kit: {e}")
    made = False
    try:
        if not folder.is_dir():  # a kit's folder may be new (the vendor's library is copied in after)
            if folder.exists() or folder.is_symlink():
                args.sub.error(f"argument DIR: {str(folder)[:200]!r} is not a folder")
            if not folder.parent.is_dir():
                args.sub.error(f"argument DIR: no folder {str(folder.parent)[:200]!r} to make {folder.name!r} in")
            made = True
    except (OSError, ValueError) as e:
        args.sub.error(f"argument DIR: cannot read {str(folder)[:200]!r} ({getattr(e, 'strerror', None) or e})")
    _writable(args.sub, "DIR", folder, base=folder.parent if made else folder)  # (made here if new)
    if made:
        print(f"made {folder}/")
    try:
        written = write(chosen.name, folder)
    except FileExistsError as e:
        args.sub.error(f"argument DIR: {e.args[0] if e.args else e} exists; nothing written")
    except OSError as e:
        args.sub.error(f"argument DIR: cannot write in {folder} ({e.strerror or e})")
    for path in written:
        print(f"wrote {path}")
    print(f"{chosen.title}: put the firmware in {folder} (docs/kits.md), then mpy-fil check {written[0]}")
    return 0


def cmd_init(args) -> int:
    from host.rig.scan.starter import starter

    if args.kit:
        return _init_kit(args)
    folder = args.folder
    try:
        if not folder.is_dir():
            args.sub.error(f"argument DIR: no folder {str(folder)[:200]!r}")
        path = folder / "rig.toml"
        safefs.refuse_link(path, "argument DIR:")  # (a dangling one would make the file where it points)
        if path.exists():
            args.sub.error(f"argument DIR: {path} exists; check it with mpy-fil check {path}")
    except (OSError, ValueError) as e:  # (a name too long, a NUL)
        args.sub.error(f"argument DIR: cannot read {str(folder)[:200]!r} ({getattr(e, 'strerror', None) or e})")
    _writable(args.sub, "DIR", folder, base=folder)
    notes: list[str] = []
    try:
        safefs.write_new(path, starter(folder, notes))
    except FileExistsError:
        args.sub.error(f"argument DIR: {path} exists; check it with mpy-fil check {path}")
    except OSError as e:
        args.sub.error(f"argument DIR: cannot read {folder} or write {path} ({e.strerror or e})")
    for note in notes:
        print(f"{args.sub.prog}: {note}", file=sys.stderr)
    print(f"wrote {path}: name the pins, pick the plant's parts, wire them; then mpy-fil check {path}")
    return 0


def cmd_migrate(args) -> int:
    """A 0.1 rig file in today's form, checked as a rig file before it is written: beside
    it (never over it but with --in-place, never through a link: host/core/safefs.py)."""
    import tomllib

    from host.rig.config import migrate
    from host.rig.config.rigfile import MAX_RIG_BYTES, rig_from_data

    sub, path = args.sub, args.rig
    out = path if args.in_place else (args.out or migrate.migrated_path(path))
    try:
        safefs.refuse_link(path, "argument RIG:")
        if not safefs.regular_file(path):
            sub.error(f"argument RIG: no rig file at {str(path)[:200]!r}")
        if path.stat().st_size > MAX_RIG_BYTES:
            sub.error(f"argument RIG: {path} is over {MAX_RIG_BYTES} bytes: not a rig file")
        text = path.read_text(encoding="utf-8")
        if out.resolve().parent != path.resolve().parent:
            sub.error(
                f"argument --out: expected a file in {path.resolve().parent} (the rig's paths are relative to it)"
            )
        if not args.in_place and out.resolve() == path.resolve():
            sub.error(f"argument --out: {out} is RIG itself: give --in-place to replace it")
        safefs.refuse_link(out, "argument --out:")
        new, moved = migrate.migrate_text(text)
        rig_from_data(out, tomllib.loads(new))  # (what is written loads, or nothing is written)
        if args.in_place:
            safefs.write_text(out, new, refuse_links=True)
        else:
            safefs.write_new(out, new)
    except FileExistsError:
        sub.error(f"argument --out: {out} exists: give another --out, or --in-place to replace RIG")
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        sub.error(f"argument RIG: cannot read {str(path)[:200]!r} or write {str(out)[:200]!r} ({e})")
    print(f"wrote {out} from {path} (0.1's kind = {moved.kind!r}): {moved.summary()}")
    for old, now in moved.renames.items():
        print(f"  signal {old} is {now} now ([wiring] and budgets)")
    for name, change in moved.budgets.items():
        for key, value in change.items():
            said = "left to its source's part" if value is None else repr(value)
            print(f"  [budgets.{migrate.toml_key(name)}] {key}: {said}")
    if "console_baud = 0" in new and "console_baud" not in text:
        print('  [board] console_baud = 0: 0.1 printed for free (docs/shim.md, "Printing takes time")')
    print(f"then: mpy-fil check {out}")
    return 0


def cmd_import_wokwi(args) -> int:
    from host.rig.config.wokwi.project import import_wokwi

    path = import_wokwi(args.folder, force=args.force)
    print(f"wrote {path}: mpy-fil check {path}, then add budgets, faults and worlds (docs/rig-file.md)")
    return 0


def cmd_list(args) -> int:
    print(f"apps ({FIRMWARE}/apps/*/rig*.toml):")
    for name, app in sorted(apps().items()):
        print(f"  {name:<18} {app.rig_file.relative_to(FIRMWARE.parent)}  {app.doc}")
    boards = pin_maps.known_boards()
    print(f"boards (firmware/boards/<name>/board.py): {', '.join(boards)}")
    from sim_plant.catalogue.docs import listing

    print("\n".join(listing()))
    return 0


def cmd_parts(args) -> int:
    """docs/parts.md's sections of every entry the catalogue has here: ours, an installed
    package's (entry points ``mpy_fil.catalogue``) and, with ``--rig``, the rig file's own."""
    from sim_plant import catalogue
    from sim_plant.catalogue.docs import render

    if args.rig:
        get_app(args.rig)  # (reads its [plant] catalogue; a ConfigError names the field)
    tables = {name: getattr(catalogue, name)() for name in catalogue.TABLES}
    if args.kinds:
        tables = {name: {k: c for k, c in table.items() if k in args.kinds} for name, table in tables.items()}
        missing = sorted(set(args.kinds) - {k for table in tables.values() for k in table})
        if missing:
            print(f"mpy-fil parts: no entry {', '.join(missing)} (mpy-fil parts lists them all)", file=sys.stderr)
            return 2
    print(render(tables, head=not args.kinds), end="")
    return 0


def cmd_replay(args) -> int:
    from host.artefacts.folder import set_boards

    trace = "the trace folder TRACE"
    out = _writable(
        args.sub,
        "--out",
        args.out or args.trace / "replay",
        inputs={trace: args.trace, **({"the firmware folder --firmware": args.firmware} if args.firmware else {})},
        owned={trace: "replay"},
        base=None if args.out else args.trace,
    )
    boards = set_boards(args.trace)
    if not boards:
        return _replay_one(args, args.trace, out)
    if args.app or args.firmware:
        args.sub.error(
            "argument --app/--firmware: a set's run folder replays each board's own firmware (name one "
            f"board's folder, e.g. {args.trace / boards[0]}, to replay it with other firmware)"
        )
    worst = 0
    for board in boards:  # (each board from its own recording: what the others sent is in it, docs/multi-board.md)
        print(f"board {board}:", flush=True)
        worst = max(worst, _replay_one(args, args.trace / board, out / board))
    return worst


def _replay_one(args, folder: Path, out: Path) -> int:
    from host.link.transport import busy_poll_wanted
    from host.rig.loop.replay import FirmwareChoice, replay

    show = _progress(f"replay {folder}")
    choice = FirmwareChoice(args.app, args.firmware, args.trust_folder)
    try:
        result = replay(
            folder,
            out,
            progress=show,
            busy_poll=busy_poll_wanted(),
            choice=choice,
            say=lambda which: print(f"replay runs the firmware in {which}", flush=True),
            ignore_manifest=args.ignore_manifest,
        )
    finally:
        _progress_done(show)
    print(f"replay trace folder: {result.folder}")
    _manifest_lines(result.manifest)
    if result.partial:
        print(f"the recording is partial ({result.partial}): compared up to its cut")
    if result.same:
        print(f"same outputs: {result.recorded} firmware outputs match the recording")
        return 0
    print(f"outputs differ: {printable(result.difference)}")
    print(f"recorded {result.recorded} firmware outputs, replay {result.replayed}")
    return EXIT_FAILED


def _manifest_lines(differs: list[str] | None) -> None:
    if differs is None:
        print("manifest: none in the trace folder (written before manifests): not checked")
    for line in differs or ():
        print(f"manifest differs: {line}")


def cmd_plot(args) -> int:
    from host.artefacts.checks import partial_reason
    from host.artefacts.folder import load_trace
    from host.report.plots import plot_trace

    trace = "the trace folder TRACE"
    out = _writable(
        args.sub,
        "--out",
        args.out or args.trace / "plots",
        inputs={trace: args.trace},
        owned={trace: "plots"},
        base=None if args.out else args.trace,
    )
    partial = partial_reason(load_trace(args.trace).header)
    if partial:
        print(f"the trace folder is partial: {partial}")
    for path in plot_trace(args.trace, out):
        print(f"plot: {path}")
    return 0


def cmd_campaign(args) -> int:
    from host.campaign import load_campaign, replay
    from host.campaign.metrics import judged_by
    from host.campaign.report import progress_line, summary_lines, write_report
    from host.campaign.runner import run_campaign
    from host.link.transport import busy_poll_wanted

    if args.replay:
        if not args.out:
            args.sub.error("argument --replay: needs --out, the campaign's folder")
        r = replay(args.out, args.replay)
        print(f"{'pass' if r['passed'] else 'FAIL'} {r['key']}: {r['message'] or 'ok'}")
        print(f"figures: {', '.join(f'{k}={v:.4g}' for k, v in r['figures'].items())}")
        print(f"trace folder: {r['artefacts']}")
        return 0 if r["passed"] else EXIT_FAILED
    if not args.rig:
        args.sub.error("the following arguments are required: RIG (or --replay KEY --out DIR)")
    overrides = {k: getattr(args, k) for k in ("seeds", "first_seed", "worlds", "seconds", "timeout_s")}
    campaign = load_campaign(args.rig, faults_file=args.faults, **overrides)
    rig_file = Path(args.rig) if Path(args.rig).is_file() else None
    root = output_root(rig_file)
    out = _writable(
        args.sub,
        "--out",
        args.out or root / "campaign" / campaign.name,
        inputs={"the campaign's file RIG": rig_file} if rig_file else None,
        base=None if args.out else root.parent,
    )
    where = args.scheduler or f"{args.workers} local worker(s)"
    total = len(campaign.tasks())
    print(
        f"campaign {campaign.name}: {total} runs ({len(campaign.faultsets)} fault set(s) x "
        f"{len(campaign.worlds)} world(s) x {campaign.seeds} seeds) on {where}; results in {out}"
    )
    started = time.monotonic()

    judged = judged_by(campaign.to_dict())[0]

    def progress(r, done, total):
        rate = done / max(time.monotonic() - started, 1e-9) * 60
        print(progress_line(r, done, total, judged, rate), flush=True)

    try:
        results = run_campaign(
            campaign,
            out,
            workers=args.workers,
            scheduler=args.scheduler,
            on_result=progress,
            busy_poll=busy_poll_wanted(),
        )
    except KeyboardInterrupt:
        print(f"interrupted: the finished runs are in {out / 'results.jsonl'}; the same command goes on from there")
        raise
    paths = write_report(out, campaign.to_dict(), results)
    print("\n".join(summary_lines(campaign.to_dict(), results)))
    print(f"campaign report: {paths['html']}")
    if args.shrink:
        from host.shrink.command import shrink_campaign

        say = lambda text: print(printable(text), flush=True)  # noqa: E731  (a run's failure quotes its console)
        shrink_campaign(campaign, results, out, workers=args.workers, say=say)
    return 0


def cmd_setup(args) -> int:
    from host.core import interpreter

    say = lambda msg: print(f"setup: {msg}", flush=True)  # noqa: E731
    version = getattr(args, "micropython", None)
    path = interpreter.setup(log=say, version=version, source=getattr(args, "source", None))
    print(f"micropython: {interpreter.version(path)} ({path})")
    rel = interpreter.release(version)
    if path == interpreter.default_path(None, rel.version):
        if path.parent.name == interpreter.build_key(rel.version):  # (the per-user cache)
            how = f"build key {path.parent.name}: its make options, patches, frozen manifest and C modules"
            say(f"MicroPython {rel.version} is in {path.parent} ({how}); other versions and builds stay beside it")
        else:
            say(f"MicroPython {rel.version} is in {path.parent} (this checkout's build); other versions stay beside it")
    print("next: pytest beside your rig file (docs/ci.md)")
    return 0


def _progress(label: str) -> MissionProgress | None:
    """Mission progress on stderr, one line rewritten in place (terminals only)."""
    if not sys.stderr.isatty():
        return None

    def rewrite(text: str) -> None:
        sys.stderr.write("\r\x1b[K" + text)
        sys.stderr.flush()

    return MissionProgress(label, rewrite=rewrite)


def _progress_done(progress: MissionProgress | None) -> None:
    if progress is not None and progress.on_screen:
        sys.stderr.write("\n")


if __name__ == "__main__":
    sys.exit(main())
