"""PIO frames the shim answers ahead (``host/rig/pio_ahead.py``; docs/shim.md, "PIO reads
answered ahead") go exactly as when every frame is its own exchange (``MPY_FIL_PIO_AHEAD=0``):
each PIO firmware of the repository below runs three ways, every frame an exchange, answered
ahead, and answered ahead with each answer played again on the host's blocks at once and
compared (``check``: a wrong answer stops the run), and each run must give the same link
trace (every record of ``trace.jsonl`` but its header: each STATE's changes, each output,
each PIO frame and bus transfer with its instant, op, bytes written and reply), the same
console and the same ground truth; where
the firmware reads a decoder by request, some frames must have been answered ahead (so the
comparison compares something) and the exchanges must be fewer."""

import pytest

from host.bench import KIT_DEMOS, kit_demo_folder, run_kit_demo, run_pio_bot
from host.core.paths import REPO
from host.pytest_plugin import rig_from_keywords
from host.rig.hardware.pio_ahead import ENV
from host.tests.conftest import FIRMWARE, bench_app

pytestmark = pytest.mark.hil

WIRE = {"body": "bench", "parts": [{"kind": "wire", "name": "w0"}]}
WAYS = ("0", "1", "check")  # every frame an exchange; answered ahead; answered ahead and checked


def trace_records(folder) -> list[str]:
    """Every record of the run's link trace but its header (which names the firmware's folder)."""
    text = (folder / "trace.jsonl").read_text()
    return [line for line in text.splitlines() if not line.startswith('{"header"')]


def three_ways(monkeypatch, tmp_path, run) -> dict:
    """``run(artefacts)`` each way: {way: (trace records, console, truth, frames answered ahead, exchanges)}."""
    out = {}
    for way in WAYS:
        monkeypatch.setenv(ENV, way)
        folder = tmp_path / f"ahead-{way}"
        console, truth, local, exchanges = run(folder)
        out[way] = (trace_records(folder), console, truth, local, exchanges)
    return out


def same(out: dict, where: str, tmp_path, answered: bool) -> None:
    exchange = out["0"]
    assert exchange[3] == 0, f"{where}: expected no frame answered ahead with {ENV}=0, got {exchange[3]}"
    for way in WAYS[1:]:
        for i, name in enumerate(("link trace", "console", "truth")):
            a, b = exchange[i], out[way][i]
            if a != b:
                first = ""
                if i == 0:
                    k = next((k for k, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
                    first = f"first difference at record {k}: {a[k] if k < len(a) else None} against "
                    first += f"{b[k] if k < len(b) else None}; "
                raise AssertionError(
                    f"{where}: expected the same {name} with {ENV}={way} as with an exchange a frame; "
                    f"{first}artefacts in {tmp_path}"
                )
        if answered:
            assert out[way][3] > 0, f"{where}: expected frames answered ahead with {ENV}={way}, got none"
            assert out[way][4] < exchange[4], (
                f"{where}: expected fewer exchanges with {ENV}={way}: {out[way][4]} against {exchange[4]}"
            )


def rig_run(app, seconds: float, **kwargs):
    def run(folder):
        rig = rig_from_keywords(app, seed=1, trace=True, artefacts=folder, **kwargs)
        rig.start()
        try:
            rig.run_for(seconds)
            console, truth = rig.console, rig.truth()
            local = rig.wiring.pio.ahead.local
            exchanges = rig.stats.link_round_trips + rig.stats.bus_round_trips
        finally:
            rig.stop()
        return console, truth, local, exchanges

    return run


def test_the_bench_pio_decoder_robot_reads_the_same_counts_with_frames_answered_ahead(monkeypatch, tmp_path):
    def run(folder):
        r = run_pio_bot(600, trace=True, artefacts=folder)
        assert r["counts"] == r["edges"], f"expected the counts equal to the plant's edges: {r}"
        return (r["reads"], r["counts"]), r["edges"], r["answered_ahead"], r["exchanges"]

    same(three_ways(monkeypatch, tmp_path, run), "host/bench/pio_bot", tmp_path, answered=True)


def test_the_3pi_2040_kits_demo_goes_the_same_with_frames_answered_ahead(monkeypatch, tmp_path):
    kit = next(d for d in KIT_DEMOS if d[0] == "pololu_3pi_2040")

    def run(folder):
        # 1 s: the button pressed at 0.2 s, the demo reads its PIO encoders as it drives from
        # 0.3 s on, at a steady rate (1,539 frames answered ahead by 1 s, 3,739 by 2 s)
        r = run_kit_demo(*kit, sim_s=1.0, trace=True, artefacts=folder)
        return r["console"], r["sim_s"], r["pio_local"], r["exchanges"]

    same(three_ways(monkeypatch, tmp_path, run), "the pololu_3pi_2040 kit's demo", tmp_path, answered=True)


def test_the_pico_pio_bot_example_goes_the_same_with_frames_answered_ahead(monkeypatch, tmp_path):
    run = rig_run(str(REPO / "examples" / "pico_pio_bot" / "rig.toml"), 1.5)
    same(three_ways(monkeypatch, tmp_path, run), "examples/pico_pio_bot", tmp_path, answered=True)


def test_the_3pi_pio_sensor_reads_go_the_same_with_frames_answered_ahead(monkeypatch, tmp_path):
    """A program that drives its pins (the QTR charge): never answered ahead, and the same."""
    folder = tmp_path / "fw"
    folder.mkdir()
    rig_file = kit_demo_folder(folder, "pololu_3pi_2040", (("kits/pololu_3pi_pio", "."),), None, None)
    run = rig_run(str(rig_file), 0.3, allow_exit=True)
    same(three_ways(monkeypatch, tmp_path, run), "the 3pi+ 2040's PIO line and bump sensors", tmp_path, answered=False)


@pytest.mark.parametrize(
    ("case", "plant", "wiring", "pins", "seconds"),
    [
        ("buffer_kinds_pio", {"body": "bench", "parts": []}, None, None, 1.0),
        (
            "pio_irq",
            {"body": "bench", "parts": [{"kind": "wire", "name": "w0"}]},
            {"SRC": "w0.in", "ECHO": "w0.out"},
            {"SRC": 4, "ECHO": 5},
            0.3,
        ),
    ],
)
def test_a_pio_test_firmware_goes_the_same_with_frames_answered_ahead(
    monkeypatch, tmp_path, case, plant, wiring, pins, seconds
):
    extra = {"wiring": wiring, "pins": pins} if wiring else {}
    app = bench_app(case, plant, board="rpi_pico_bench", **extra)
    run = rig_run(app, seconds, main_dir=FIRMWARE / case, allow_exit=True)
    same(three_ways(monkeypatch, tmp_path, run), f"host/tests/firmware/{case}", tmp_path, answered=False)
