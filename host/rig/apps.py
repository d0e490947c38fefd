"""Firmware applications the harness knows how to run: where the code is, which plant
it drives, how the board's named pins are wired to the plant's signals, and which
timing budgets apply."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from host.core.errors import ConfigError
from host.core.paths import FIRMWARE
from host.rig.budgets import Budget, ComputeBudget, LatencyBudget, PeriodBudget, PulseBudget
from host.rig.wiring import PROBE_PREFIX
from sim_plant.plant import Plant
from sim_plant.pool import BODY_LENGTH_M, BODY_WIDTH_M, PoolCleaner
from sim_plant.rover import RoverRoom
from sim_plant.world import POOL_LENGTH_M


@dataclass
class App:
    name: str
    default_board: str
    make_plant: Callable[..., Plant]
    wiring: dict[str, str]
    make_budgets: Callable[[Plant], list[Budget]] = lambda plant: []
    """The app's budgets for a plant: a budget's expected value comes from the plant it
    measures (the sonar period is the plant's ``sonar_period_us``)."""
    boards: tuple[str, ...] = ()
    doc: str = ""
    extra: dict = field(default_factory=dict)
    folder: Path | None = None  # default: firmware/apps/<name>
    worlds: dict[str, dict] = field(default_factory=lambda: {"default": {}})
    """Named worlds: the plant options that build each (the first is the default)."""

    @property
    def path(self) -> Path:
        return self.folder or FIRMWARE / "apps" / self.name

    def firmware_path(self, board_path: Path) -> list[Path]:
        """Folders as a board's filesystem has them: the app at /, drivers in /lib."""
        return [self.path, board_path, FIRMWARE / "lib"]


def rover_budgets(plant: RoverRoom) -> list[Budget]:
    return [
        PeriodBudget(
            "control.period",
            PROBE_PREFIX + "control",
            period_us=50_000,
            tolerance_us=1_000,
            description="control step every 50 ms (probe pin toggles)",
        ),
        PeriodBudget(
            "sonar.period",
            "sonar.adc",
            period_us=plant.sonar_period_us,
            tolerance_us=1_000,
            description=f"a new sonar range every {plant.sonar_period_us / 1000:g} ms",
        ),
        LatencyBudget(
            "sonar.latency",
            "sonar.adc",
            limit_us=50_000,
            description="each new sonar sample read within one 50 ms quantum",
        ),
        ComputeBudget(
            "control.compute",
            "compute",
            limit_us=50_000,
            description="wall-clock us the firmware ran per wake (informational)",
        ),
    ]


ROVER_WIRING = {
    "MOTOR_L_IN1": "motor_l.in1",
    "MOTOR_L_IN2": "motor_l.in2",
    "MOTOR_L_PWM": "motor_l.pwm",
    "MOTOR_R_IN1": "motor_r.in1",
    "MOTOR_R_IN2": "motor_r.in2",
    "MOTOR_R_PWM": "motor_r.pwm",
    "ENC_L_A": "enc_l.a",
    "ENC_L_B": "enc_l.b",
    "ENC_R_A": "enc_r.a",
    "ENC_R_B": "enc_r.b",
    "SONAR_ADC": "sonar.adc",
    "BUMPER": "bumper",
    "LOOP_PROBE": PROBE_PREFIX + "control",
}


def pool_plant(**options) -> PoolCleaner:
    """The pool cleaner as its mission starts (seed 000 §7.3.3): in a corner, the
    front bumper (bumper1) 1 cm off the end wall, its side 2 cm off the side wall."""
    length_m = options.get("pool_length_m", POOL_LENGTH_M)
    options.setdefault("start_pose", (length_m - BODY_LENGTH_M / 2 - 0.01, BODY_WIDTH_M / 2 + 0.02, 0.0))
    return PoolCleaner(**options)


def pool_adc_plant(**options) -> PoolCleaner:
    return pool_plant(sonar="adc", **options)


def pool_budgets(plant: PoolCleaner) -> list[Budget]:
    sonar_source = "sonar.uart" if plant.sonar == "nmea" else "sonar_l.adc"
    uart = sonar_source.endswith(".uart")
    period_ms = f"{plant.sonar_period_us / 1000:g} ms"
    return [
        PeriodBudget(
            "control.period",
            PROBE_PREFIX + "control",
            period_us=50_000,
            tolerance_us=1_000,
            description="control step every 50 ms (probe pin toggles)",
        ),
        PeriodBudget(
            "sonar.period",
            sonar_source,
            period_us=plant.sonar_period_us,
            tolerance_us=1_000,
            marker=b"$" if uart else None,
            description=f"a sonar sentence starts every {period_ms}"
            if uart
            else f"a new sonar sample every {period_ms}",
        ),
        LatencyBudget(
            "sonar.latency",
            sonar_source,
            limit_us=50_000,
            description="each sonar sample read within one 50 ms quantum",
        ),
        PulseBudget(
            "track.stop",
            ("track_l.stop", "track_r.stop"),
            limit_us=300_000,
            description=f"a track stop lasts at most 300 ms of its {period_ms} slot",
        ),
        ComputeBudget(
            "control.compute",
            "compute",
            limit_us=50_000,
            description="wall-clock us the firmware ran per wake (informational)",
        ),
    ]


POOL_WIRING = {
    "TRACK_L_STOP": "track_l.stop",
    "TRACK_R_STOP": "track_r.stop",
    "BUMPER_FRONT": "bumper_front",
    "BUMPER_REAR": "bumper_rear",
    "SONAR_UART": "sonar.uart",
    "SONAR_SELECT": "sonar.select",
    "LOOP_PROBE": PROBE_PREFIX + "control",
}
POOL_ADC_WIRING = {
    **{k: v for k, v in POOL_WIRING.items() if not k.startswith("SONAR_")},
    "SONAR_L_ADC": "sonar_l.adc",
    "SONAR_R_ADC": "sonar_r.adc",
}

APPS = {
    "rover": App(
        name="rover",
        default_board="esp32_devkitc",
        boards=("esp32_devkitc", "rpi_pico"),
        make_plant=RoverRoom,
        wiring=ROVER_WIRING,
        make_budgets=rover_budgets,
        doc="differential-drive rover in a room: sonar slow-down, bump, back off, turn",
        worlds={
            "room": {},
            "long-room": {"room_w_m": 8.0, "room_h_m": 4.0},
            "small-room": {"room_w_m": 3.0, "room_h_m": 3.0, "start_pose": (1.0, 1.5, 0.0)},
        },
    ),
    "pool_cleaner": App(
        name="pool_cleaner",
        default_board="esp32_pool_cleaner",
        boards=("esp32_pool_cleaner",),
        make_plant=pool_plant,
        wiring=POOL_WIRING,
        make_budgets=pool_budgets,
        doc="WEDA B400 pool cleaner (seeds 000/001): lanes by side sonar on NMEA, Kalman filter, bumpers",
    ),
    "pool_cleaner_adc": App(
        name="pool_cleaner_adc",
        default_board="esp32_pool_cleaner_adc",
        boards=("esp32_pool_cleaner_adc",),
        make_plant=pool_adc_plant,
        wiring=POOL_ADC_WIRING,
        make_budgets=pool_budgets,
        doc="the pool cleaner built for the ADC sonar option (same firmware, another board file)",
        folder=FIRMWARE / "apps" / "pool_cleaner",
    ),
}


def get_app(name: str) -> App:
    try:
        return APPS[name]
    except KeyError:
        raise ConfigError(f"app: unknown app {name!r} (known: {', '.join(sorted(APPS))})") from None
