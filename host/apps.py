"""Firmware applications the harness knows how to run: where the code is, which plant
it drives, how the board's named pins are wired to the plant's signals, and which
timing budgets apply."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from host.boards import REPO
from host.budgets import Budget, ComputeBudget, LatencyBudget, PeriodBudget
from host.errors import ConfigError
from sim_plant.plant import Plant
from sim_plant.rover import RoverRoom

FIRMWARE = REPO / "firmware"
PROBE = "probe:"
"""Wiring target prefix for a pin that only the harness watches (a logic-analyser probe)."""


@dataclass
class App:
    name: str
    default_board: str
    make_plant: Callable[..., Plant]
    wiring: dict[str, str]
    make_budgets: Callable[[], list[Budget]] = list
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


def rover_budgets() -> list[Budget]:
    return [
        PeriodBudget(
            "control.period",
            PROBE + "control",
            period_us=50_000,
            tolerance_us=1_000,
            description="control step every 50 ms (probe pin toggles)",
        ),
        PeriodBudget(
            "sonar.period",
            "sonar.adc",
            period_us=500_000,
            tolerance_us=1_000,
            description="a new sonar range every 500 ms",
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
    "LOOP_PROBE": PROBE + "control",
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
}


def get_app(name: str) -> App:
    try:
        return APPS[name]
    except KeyError:
        raise ConfigError(f"app: unknown app {name!r} (known: {', '.join(sorted(APPS))})") from None
