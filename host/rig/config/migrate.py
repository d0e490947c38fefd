"""Rig files of 0.1 in today's form: ``[plant] kind = "rover_room"`` with ``[plant.options]``
becomes ``[plant] body = ...`` with its ``[[plant.parts]]`` (``docs/rig-file.md``, "From 0.1").

0.1 had seven plant kinds, each a class with options; each is now a body and parts of the
catalogue, and our apps' rig files were moved over one by one with their link traces
unchanged (``hil_tests/test_app_digests.py``). :func:`migrate` does the same for any 0.1
rig file: the kind's plant at its defaults as a body and parts (the tables below, as the
apps' moves wrote them), each ``[plant.options]`` and ``[worlds.*]`` option put where it
lives now (a body option, or ``<part name>.<option>``), the signals that were renamed
(``bumper`` is ``bumper.out``: a part's signals are ``<name>.<signal>``) renamed in
``[wiring]`` and budgets, a budget period ``"plant.<option>"`` given as the number or left
to the part that drives its source, and ``[board] console_baud = 0`` (0.1 printed for free).
An option with no place today (``motor_rpm``, an analog ranger on the two-wheel robot) is
refused by name (a :class:`MigrationError`) rather than dropped.

:func:`migrate_text` keeps the rest of the file as it is, comments included; ``mpy-fil
migrate RIG`` writes it beside the file (``host/cli.py``); ``load_rig`` names the new form in
its one error for a 0.1 file (:func:`message`).
"""

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import tomllib

from host.core.errors import ConfigError
from host.core.tomltext import key as toml_key
from host.core.tomltext import value as toml_value

RANGER_V_PER_M = 0.25375246062992124  # the 0.1 rover's and lab robot's sonar law (their rig files since)


class MigrationError(ConfigError):
    """A 0.1 rig file that cannot be written in today's form as it is: the message names
    the option and why."""


@dataclass
class Migrated:
    """A 0.1 rig file's plant in today's form: ``plant`` (the ``[plant]`` table with its
    ``parts``), ``worlds`` (name -> options), ``renames`` (signal then -> signal now),
    ``budgets`` (name -> {key: new value, or None: left out})."""

    kind: str
    plant: dict
    worlds: dict
    renames: dict
    budgets: dict = field(default_factory=dict)

    def summary(self) -> str:
        """``body = "differential" with parts motor_l (dc_motor), ...``."""
        parts = ", ".join(f"{p['name']} ({p['kind']})" for p in self.plant["parts"])
        return f'body = "{self.plant["body"]}" with parts {parts or "none"}'


# -- the kinds of 0.1 -----------------------------------------------------------------------


def _motors(bridge: str, deadband, time_constant_ms) -> list:
    return [
        {"kind": "dc_motor", "name": f"motor_{s[0]}", "bridge": bridge, "drives": s, "deadband_duty": deadband,
         "time_constant_ms": time_constant_ms}
        for s in ("left", "right")
    ]  # fmt: skip


def _encoders(**options) -> list:
    return [{"kind": "encoder", "name": f"enc_{s[0]}", **options, "wheel": s} for s in ("left", "right")]


# Where a 0.1 option goes now: a function of its value and its name giving (key, value)
# pairs, a key being a body option or ``<part name>.<option>`` (as a world or --param names it).


def _pair(name: str, option: str) -> Callable:
    """An option of both parts ``<name>_l`` and ``<name>_r``."""
    return lambda v, _: [(f"{name}_l.{option}", v), (f"{name}_r.{option}", v)]


def _each(names, option: str) -> Callable:
    return lambda v, _: [(f"{n}.{option}", v) for n in names]


def _per_side(name: str, option: str) -> Callable:
    """A ``[left, right]`` pair of values: one to each part."""
    return lambda v, _: [(f"{name}_l.{option}", v[0]), (f"{name}_r.{option}", v[1])]


def _body(option: str | None = None, scale: float = 1.0) -> Callable:
    """The body's option of the same name (or ``option``), its value times ``scale``."""
    return lambda v, name: [(option or name, v if scale == 1.0 else v * scale)]


def _part(key: str) -> Callable:
    return lambda v, _: [(key, v)]


def _values(option: str, table: dict) -> Callable:
    """A named value that is now another name (or several body options: a 0.1 world)."""

    def place(v, _):
        if v not in table:
            raise MigrationError(f"{option} = {v!r}: expected one of {', '.join(map(repr, table))}")
        now = table[v]
        return list(now.items()) if isinstance(now, dict) else [(option, now)]

    return place


@dataclass(frozen=True)
class Kind:
    """A 0.1 kind: its options' defaults (those of its class), the plant at those options
    as a body and parts (``build`` takes the options and may change the parts:
    ``structural`` options, which a world cannot set), where each other option goes now,
    and the signals renamed."""

    defaults: dict
    build: Callable
    places: dict
    structural: tuple = ()
    renames: Callable = lambda opts: {}


def _rover(o: dict) -> dict:
    ranger = {"noise_sd_m": 0.01, "min_range_m": 0.03, "max_range_m": 4.0, "period_us": 500000, "phase_us": 20000}
    return {
        "body": "differential", "room_w_m": 5.0, "room_h_m": 4.0, "start_pose": [1.0, 2.0, 0.0],
        "body_radius_m": o["body_radius_m"], "wheel_radius_m": 0.033, "track_m": 0.23, "v_max_m_s": 0.5,
        "parts": [
            *_motors("tb6612", 0.08, 0),
            *_encoders(on="wheel", lines_per_rev=20),
            {"kind": "bumper", "name": "bumper", "half_arc_deg": 70},
            {"kind": "analog_ranger", "name": "sonar", "mount": {"x_m": o["body_radius_m"], "y_m": 0.0,
             "heading_deg": 0}, **ranger, "volts_per_m": RANGER_V_PER_M},
            {"kind": "coverage", "name": "floor", "coverage_cell_m": 0.1},
        ],
    }  # fmt: skip


ROVER = Kind(
    defaults={
        "room_w_m": 5.0,
        "room_h_m": 4.0,
        "start_pose": (1.0, 2.0, 0.0),
        "body_radius_m": 0.17,
        "wheel_radius_m": 0.033,
        "track_m": 0.23,
        "v_max_m_s": 0.5,
        "deadband_duty": 0.08,
        "encoder_cpr": 20,
        "sonar_period_us": 500000,
        "sonar_phase_us": 20000,
        "sonar_noise_m": 0.01,
        "sonar_min_m": 0.03,
        "sonar_max_m": 4.0,
        "adc_bits": 12,
        "adc_vref": 3.3,
        "bumper_bounce_us": 0,
    },  # fmt: skip
    build=_rover,
    places={
        **dict.fromkeys(("room_w_m", "room_h_m", "start_pose", "wheel_radius_m", "track_m", "v_max_m_s"), _body()),
        "deadband_duty": _pair("motor", "deadband_duty"),
        "encoder_cpr": _pair("enc", "lines_per_rev"),
        "sonar_period_us": _part("sonar.period_us"),
        "sonar_phase_us": _part("sonar.phase_us"),
        "sonar_noise_m": _part("sonar.noise_sd_m"),
        "sonar_min_m": _part("sonar.min_range_m"),
        "sonar_max_m": _part("sonar.max_range_m"),
        "bumper_bounce_us": _part("bumper.bounce_us"),
    },
    structural=("body_radius_m",),  # (the sonar's mount is at the body's edge)
    renames=lambda o: {"bumper": "bumper.out"},
)


def _pool(o: dict) -> dict:
    sonar = o["sonar"]
    if sonar == "nmea":
        sonars = [
            {"kind": "echo_sounder", "name": "sonar", "mount": {"y_m": 0.24, "heading_deg": 90}, "transducers": 2}
        ]
    elif sonar == "adc":
        sonars = [
            {"kind": "echo_sounder", "name": f"sonar_{s}", "output": "adc", "mount": {"y_m": y, "heading_deg": h}}
            for s, y, h in (("l", 0.24, 90), ("r", -0.24, -90))
        ]
    else:
        raise MigrationError(f"sonar: expected 'nmea' or 'adc', got {sonar!r}")
    for part in sonars:  # (each sounder has the 0.1 sonar's figures, where they were set)
        for old, new in SOUNDER:
            if o[old] != POOL_DEFAULTS[old]:
                part[new] = o[old]
    return {
        "body": "tracked",
        "parts": [
            {"kind": "track", "name": "track_l", "side": "left"},
            {"kind": "track", "name": "track_r", "side": "right"},
            {"kind": "bumper", "name": "bumper_front", "mount": {"heading_deg": 0}, "half_arc_deg": 60},
            {"kind": "bumper", "name": "bumper_rear", "mount": {"heading_deg": 180}, "half_arc_deg": 60},
            *sonars,
        ],
    }


SOUNDER = (
    ("sonar_period_us", "period_us"),
    ("sonar_phase_us", "phase_us"),
    ("bytes_per_change", "bytes_per_change"),
    ("switch_settle_s", "switch_settle_s"),
)
POOL_DEFAULTS = {
    "pool_length_m": 25.0, "pool_width_m": 8.0, "start_pose": (0.46, 0.5, 0.0), "speed_m_s": 0.3, "track_m": 0.4,
    "steering": "measured", "steer_scatter_rel": 0.13, "reversal_pause_ms": 1000.0, "kick_mean_rad": -0.0174,
    "kick_sd_rad": 0.0348, "sonar": "nmea", "sonar_period_us": 500000, "sonar_phase_us": 100000,
    "sonar_options": None, "bytes_per_change": 1, "switch_settle_s": 0.0, "bumper_bounce_us": 0,
    "coverage_cell_m": 0.1, "sonar_faults": (),
}  # fmt: skip
POOL = Kind(
    defaults=POOL_DEFAULTS,
    build=_pool,
    places={
        **dict.fromkeys(
            (
                "pool_length_m",
                "pool_width_m",
                "start_pose",
                "speed_m_s",
                "track_m",
                "steering",
                "steer_scatter_rel",
                "reversal_pause_ms",
                "kick_mean_rad",
                "kick_sd_rad",
                "coverage_cell_m",
            ),
            _body(),
        ),  # fmt: skip
        "bumper_bounce_us": _each(("bumper_front", "bumper_rear"), "bounce_us"),
    },
    structural=("sonar", *(old for old, _ in SOUNDER)),
    renames=lambda o: {"bumper_front": "bumper_front.out", "bumper_rear": "bumper_rear.out"},
)


def _vacuum(o: dict) -> dict:
    return {
        "body": "differential", "world": "vacuum_room", "room_w_m": 5.0, "room_h_m": 4.0, "body_radius_m": 0.125,
        "wheel_radius_m": 0.0325, "track_m": 0.18, "v_max_m_s": 0.35,
        "parts": [
            *_motors("l298n", 0.25, 0),
            *_encoders(channels="single", on="wheel", lines_per_rev=20),
            {"kind": "servo", "name": "servo", "mount": {"x_m": 0.1, "y_m": 0.0, "heading_deg": 0},
             "slew_deg_per_s": 500},
            {"kind": "hcsr04", "name": "sonar", "mount": {"x_m": 0.1, "y_m": 0.0, "heading_deg": 0},
             "on_servo": "servo", "trigger_min_us": 10},
            {"kind": "coverage", "name": "floor", "coverage_cell_m": 0.05},
        ],
    }  # fmt: skip


VACUUM = Kind(
    defaults={
        "world": "vacuum_room",
        "room_w_m": 5.0,
        "room_h_m": 4.0,
        "route": ((0.6, 1.0), (4.2, 1.1), (4.0, 3.0), (1.0, 2.9)),
        "start_pose": None,
        "wheel_diameter_m": 0.065,
        "track_m": 0.18,
        "v_max_m_s": 0.35,
        "deadband_duty": 0.25,
        "motor_gains": (1.0, 1.0),
        "motor_time_constant_ms": 0.0,
        "slots_per_rev": 20,
        "sonar_noise_sd_m": 0.003,
        "bumper": False,
        "bumper_bounce_us": 0,
        "coverage_cell_m": 0.05,
    },  # fmt: skip
    build=_vacuum,
    places={
        "world": _values("world", {"vacuum_room": "vacuum_room", "empty": "room"}),
        **dict.fromkeys(("room_w_m", "room_h_m", "route", "start_pose", "track_m", "v_max_m_s"), _body()),
        "wheel_diameter_m": _body("wheel_radius_m", 0.5),
        "deadband_duty": _pair("motor", "deadband_duty"),
        "motor_gains": _per_side("motor", "gain"),
        "motor_time_constant_ms": _pair("motor", "time_constant_ms"),
        "slots_per_rev": _pair("enc", "lines_per_rev"),
        "sonar_noise_sd_m": _part("sonar.noise_sd_m"),
        "coverage_cell_m": _part("floor.coverage_cell_m"),
    },
    renames=lambda o: {"enc_l": "enc_l.out", "enc_r": "enc_r.out"},
)

DUCT_WORLDS = {
    "one_right_branch": "duct",
    "multi_branch": "multi_branch_duct",
    "straight_1m": "straight_duct",
    "bench": "bench_duct",
}


def _duct(o: dict) -> dict:
    sonars = [
        {"kind": "amplitude_sonar", "name": n, "mount": {"x_m": x, "y_m": y, "heading_deg": h}}
        for n, x, y, h in (("sonar_f", 0.04, 0.0, 0), ("sonar_l", -0.1, 0.09, 90), ("sonar_r", -0.1, -0.09, -90))
    ]
    for sonar, gain in zip(sonars, (1.0, 1.05, 0.95)):
        if gain != 1.0:
            sonar["gain"] = gain
    link = [{"kind": "record_link", "name": "link"}] if o["link"] else []
    return {
        "body": "differential", "world": "duct", "wheel_radius_m": 0.03, "track_m": 0.18, "v_max_m_s": 0.4,
        "outline": [[-0.04, 0.0, 0.1], [-0.12, 0.0, 0.1]], "spin_slip": 0.3,
        "parts": [
            *_motors("dir_pwm", 0.1, 0),
            *_encoders(channels="single", on="motor", lines_per_rev=8, gear_ratio=6.0),
            *sonars,
            *link,
            {"kind": "tether", "name": "tether", "snag_p": 0},
        ],
    }  # fmt: skip


DUCT = Kind(
    defaults={
        "world": "one_right_branch",
        "start_pose": (0.3, 0.2, 0.0),
        "wheel_diameter_m": 0.06,
        "track_m": 0.18,
        "v_max_m_s": 0.4,
        "deadband_duty": 0.1,
        "motor_gains": (1.0, 1.0),
        "motor_time_constant_ms": 0.0,
        "slots_per_rev": 8,
        "gear_ratio": 6.0,
        "spin_slip": 0.3,
        "sonar_gains": (1.0, 1.05, 0.95),
        "sonar_options": None,
        "bumper": False,
        "bumper_bounce_us": 0,
        "link": False,
        "link_options": None,
        "snag_p": 0.0,
        "snag_options": None,
    },  # fmt: skip
    build=_duct,
    places={
        "world": _values("world", DUCT_WORLDS),
        **dict.fromkeys(("start_pose", "track_m", "v_max_m_s", "spin_slip"), _body()),
        "wheel_diameter_m": _body("wheel_radius_m", 0.5),
        "deadband_duty": _pair("motor", "deadband_duty"),
        "motor_gains": _per_side("motor", "gain"),
        "motor_time_constant_ms": _pair("motor", "time_constant_ms"),
        "slots_per_rev": _pair("enc", "lines_per_rev"),
        "gear_ratio": _pair("enc", "gear_ratio"),
        "sonar_gains": lambda v, _: [(f"sonar_{s}.gain", g) for s, g in zip("flr", v)],
        "snag_p": _part("tether.snag_p"),
    },
    structural=("link",),
    renames=lambda o: {"enc_l": "enc_l.out", "enc_r": "enc_r.out"},
)

LAB_WORLDS = {
    "arena": {"world": "room", "room_w_m": 4.0, "room_h_m": 4.0, "start_pose": [1.0, 1.0, 0.0]},
    "canyon": {"world": "canyon", "room_w_m": None, "room_h_m": None, "start_pose": [0.3, 0.2, 0.0]},
}
"""The lab robot's 0.1 worlds as the differential body's options (None: the body's default)."""


def _lab(o: dict) -> dict:
    rangers = [
        {"kind": "analog_ranger", "name": n, "mount": {"x_m": x, "y_m": y, "heading_deg": h}, "noise_sd_m": 0.01,
         "min_range_m": 0.15, "max_range_m": 5.0, "volts_per_m": RANGER_V_PER_M, "period_us": 100000,
         "phase_us": phase, "triggered": o["sonar_rx"]}
        for n, x, y, h, phase in (
            ("sonar_f", 0.14, 0.0, 0.0, 20000),
            ("sonar_l", 0.0, 0.14, 90.0, 70000),
            ("sonar_lf", 0.09899494936611666, 0.09899494936611666, 45.0, 45000),
        )
    ]  # fmt: skip
    trigger = [{"kind": "ranger_trigger", "name": "sonar", "rangers": ["sonar_f", "sonar_l", "sonar_lf"],
                "ranging_us": o["sonar_ranging_us"]}] if o["sonar_rx"] else []  # fmt: skip
    return {
        "body": "differential", "world": "room", "room_w_m": 4.0, "room_h_m": 4.0, "start_pose": [1.0, 1.0, 0.0],
        "body_radius_m": 0.14, "wheel_radius_m": 0.035, "track_m": 0.2, "v_max_m_s": 0.5,
        "parts": [
            *_motors("drv8833", 0.05, 0.0),
            *_encoders(on="motor", lines_per_rev=10, gear_ratio=2.0),
            *rangers,
            *trigger,
            {"kind": "jumper", "name": "jumper", "fitted": False},
        ],
    }  # fmt: skip


LAB = Kind(
    defaults={
        "world": "arena",
        "start_pose": None,
        "wheel_radius_m": 0.035,
        "track_m": 0.2,
        "v_max_m_s": 0.5,
        "deadband_duty": 0.05,
        "motor_gains": (1.0, 1.0),
        "motor_time_constant_ms": 0.0,
        "lines_per_rev": 10,
        "gear_ratio": 2.0,
        "polarity": (1, 1),
        "spin_slip": 0.0,
        "wheel_slip_sd": 0.0,
        "slip_period_us": 100000,
        "missed_edge_p": 0.0,
        "sonar_period_us": 100000,
        "sonar_noise_m": 0.01,
        "sonar_rx": False,
        "sonar_ranging_us": 49000,
        "program_jumper": False,
        "bumper": False,
        "bumper_bounce_us": 0,
    },  # fmt: skip
    build=_lab,
    places={
        "world": _values("world", LAB_WORLDS),
        **dict.fromkeys(
            ("start_pose", "wheel_radius_m", "track_m", "v_max_m_s", "spin_slip", "wheel_slip_sd", "slip_period_us"),
            _body(),
        ),
        "deadband_duty": _pair("motor", "deadband_duty"),
        "motor_gains": _per_side("motor", "gain"),
        "motor_time_constant_ms": _pair("motor", "time_constant_ms"),
        "lines_per_rev": _pair("enc", "lines_per_rev"),
        "gear_ratio": _pair("enc", "gear_ratio"),
        "polarity": _per_side("enc", "polarity"),
        "missed_edge_p": _pair("enc", "missed_edge_p"),
        "sonar_noise_m": _each(("sonar_f", "sonar_l", "sonar_lf"), "noise_sd_m"),
        "program_jumper": _part("jumper.fitted"),
    },
    structural=("sonar_rx", "sonar_ranging_us"),
    renames=lambda o: {"jumper": "jumper.out"},
)


def _two_wheel(o: dict) -> dict:
    parts = _motors(o["bridge"], 0.1, 0)
    if o["standby"]:
        parts.append({"kind": "standby", "name": "motor"})
    if o["encoder"] in ("quadrature", "single"):
        channels = {"channels": "single"} if o["encoder"] == "single" else {}
        parts += _encoders(**channels, lines_per_rev=7, gear_ratio=20)
    elif o["encoder"] != "none":
        raise MigrationError(f"encoder: expected 'quadrature', 'single' or 'none', got {o['encoder']!r}")
    if o["bumper"]:
        parts.append({"kind": "bumper", "name": "bumper"})
    if o["ranger"] == "hcsr04":
        parts.append({"kind": "hcsr04", "name": "sonar", "mount": {"x_m": o["body_radius_m"], "y_m": 0.0,
                      "heading_deg": 0}})  # fmt: skip
    elif o["ranger"] != "none":
        raise MigrationError(f"ranger = {o['ranger']!r}: write the ranger as a part (analog_ranger, docs/parts.md)")
    presses: dict = {}
    for press in o["presses"]:
        if not (isinstance(press, (list, tuple)) and len(press) == 3 and press[0] in o["buttons"]):
            raise MigrationError(f"presses: expected [button, t_press_s, t_release_s] of {list(o['buttons'])}, "
                                 f"got {press!r}")  # fmt: skip
        presses.setdefault(press[0], []).append([press[1], press[2]])
    for name in o["buttons"]:
        button = {"kind": "button", "name": name, "presses": presses.get(name, [])}
        parts.append({**button, "bounce_us": o["button_bounce_us"]} if o["button_bounce_us"] else button)
    radius = {"body_radius_m": o["body_radius_m"]} if o["body_radius_m"] != 0.08 else {}
    return {"body": "differential", **radius, "parts": parts}  # (the body's defaults are the kind's)


TWO_WHEEL_DEFAULTS = {
    "world": "room", "room_w_m": 3.0, "room_h_m": 2.0, "obstacles": (), "start_pose": None, "body_radius_m": 0.08,
    "wheel_radius_m": 0.0325, "track_m": 0.15, "v_max_m_s": 0.4, "motor_rpm": None, "deadband_duty": 0.1,
    "motor_gains": (1.0, 1.0), "motor_time_constant_ms": 0, "bridge": "tb6612", "standby": False,
    "encoder": "quadrature", "encoder_cpr": 7, "gear_ratio": 20, "encoder_polarity": (1, 1), "ranger": "hcsr04",
    "ranger_noise_sd_m": 0.003, "hcsr04_trigger_min_us": 2, "ranger_period_us": 50000, "bumper": True,
    "bumper_bounce_us": 0, "buttons": (), "presses": (), "button_bounce_us": 0, "line_sensors": (), "tape": (),
    "tape_width_m": 0.019, "tape_u16": 58000, "floor_u16": 6000, "floor_period_us": 1000, "placements": (),
}  # fmt: skip

TWO_WHEEL = Kind(
    defaults=TWO_WHEEL_DEFAULTS,
    build=_two_wheel,
    places={
        **dict.fromkeys(
            (
                "world",
                "room_w_m",
                "room_h_m",
                "obstacles",
                "start_pose",
                "wheel_radius_m",
                "track_m",
                "v_max_m_s",
                "tape",
                "tape_width_m",
            ),
            _body(),
        ),  # fmt: skip
        "deadband_duty": _pair("motor", "deadband_duty"),
        "motor_time_constant_ms": _pair("motor", "time_constant_ms"),
        "motor_gains": _per_side("motor", "gain"),
        "encoder_cpr": _pair("enc", "lines_per_rev"),
        "gear_ratio": _pair("enc", "gear_ratio"),
        "encoder_polarity": _per_side("enc", "polarity"),
        "ranger_noise_sd_m": _part("sonar.noise_sd_m"),
        "hcsr04_trigger_min_us": _part("sonar.trigger_min_us"),
        "bumper_bounce_us": _part("bumper.bounce_us"),
    },
    structural=(
        "bridge",
        "standby",
        "encoder",
        "ranger",
        "bumper",
        "buttons",
        "presses",
        "button_bounce_us",
        "body_radius_m",
    ),  # fmt: skip
    renames=lambda o: {
        **({"bumper": "bumper.out"} if o["bumper"] else {}),
        **({"enc_l": "enc_l.out", "enc_r": "enc_r.out"} if o["encoder"] == "single" else {}),
        **{f"button.{b}": f"{b}.out" for b in o["buttons"]},
    },
)


def _wires(o: dict) -> dict:
    n = o["n"]
    if not (isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= 32):
        raise MigrationError(f"n: expected 1 to 32 wires, got {n!r}")
    return {"body": "bench", "parts": [{"kind": "wire", "name": f"w{i}"} for i in range(n)]}


WIRES = Kind(defaults={"n": 4}, build=_wires, places={}, structural=("n",))

KINDS = {
    "two_wheel": TWO_WHEEL,
    "rover_room": ROVER,
    "pool_cleaner": POOL,
    "duct_robot": DUCT,
    "vacuum_robot": VACUUM,
    "lab_robot": LAB,
    "wires": WIRES,
}
"""0.1's plant kinds (``sim_plant/kinds.py`` then), by name."""


# -- a rig file's data ----------------------------------------------------------------------


def is_01(data: dict) -> bool:
    """A rig file's tables in 0.1's form: ``[plant] kind`` (and no ``body``)."""
    plant = data.get("plant")
    return isinstance(plant, dict) and "kind" in plant and "body" not in plant


def migrate(data: dict) -> Migrated:
    """A 0.1 rig file's tables (as TOML reads them) in today's form; a MigrationError names
    the field that has no place today."""
    plant = data["plant"]
    kind_name = plant.get("kind")
    if kind_name not in KINDS:
        known = ", ".join(KINDS)
        raise MigrationError(f"[plant] kind: expected one of 0.1's kinds ({known}), got {str(kind_name)[:60]!r}")
    kind = KINDS[kind_name]
    extra = sorted(set(plant) - {"kind", "options"})
    if extra:
        raise MigrationError(f"[plant] {extra[0]}: 0.1 had [plant] kind and [plant.options] only")
    given = plant.get("options", {})
    if not isinstance(given, dict):
        raise MigrationError("[plant.options]: expected a table")
    _known(kind_name, kind, given, "[plant.options]")
    opts = {**kind.defaults, **given}
    if "world" in given and "world" in kind.places:  # (a world first: its options under the others)
        given = {"world": given["world"], **given}
    table = kind.build(opts)
    _place(table, kind, {k: v for k, v in given.items() if k not in kind.structural}, "[plant.options]", into=table)
    worlds = {}
    for name, world in (data.get("worlds") or {"default": {}}).items():
        field_name = f"[worlds.{name}]"
        if not isinstance(world, dict):
            raise MigrationError(f"{field_name}: expected a table of plant options")
        _known(kind_name, kind, world, field_name)
        fixed = [k for k in world if k in kind.structural and world[k] != opts[k]]
        if fixed:
            raise MigrationError(
                f"{field_name} {fixed[0]}: a world sets body and part options only, and this one changes the parts: "
                f"give it its own rig file"
            )
        worlds[name] = {}
        _place(table, kind, {k: v for k, v in world.items() if k not in kind.structural}, field_name, into=None,
               world=worlds[name])  # fmt: skip
    renames = kind.renames(opts)
    return Migrated(kind_name, table, worlds, renames, _budgets(data.get("budgets", {}), kind, table, renames))


def _known(kind_name: str, kind: Kind, given: dict, field_name: str) -> None:
    for name, value in given.items():
        if name not in kind.defaults:
            known = ", ".join(kind.defaults)
            raise MigrationError(f"{field_name} {name}: 0.1's {kind_name} had no such option (options: {known})")
        if name not in kind.places and name not in kind.structural and value != kind.defaults[name]:
            raise MigrationError(
                f"{field_name} {name}: 0.1's {kind_name} option has no place in today's parts as it is: "
                f"write the plant as a body and parts (docs/parts.md)"
            )


def _place(table: dict, kind: Kind, given: dict, field_name: str, into, world: dict | None = None) -> None:
    """Each option of ``given`` put where it lives now: into the ``[plant]`` table (``into``)
    or a world's table (``world``: keys as ``--param`` takes them)."""
    parts = {p["name"]: p for p in table["parts"]}
    for name, value in given.items():
        if name not in kind.places:
            continue  # (its 0.1 default: nothing to say)
        place = kind.places[name]
        try:
            keys = place(_plain(value), name)
        except (MigrationError, TypeError, IndexError) as e:
            raise MigrationError(f"{field_name} {name}: {e}") from None
        for key, now in keys:
            part, _, option = key.rpartition(".")
            if part and part not in parts:
                raise MigrationError(f"{field_name} {name}: this rig's plant has no part {part!r} for it")
            if world is not None:
                world[key] = table_default(table, key) if now is None else now
            elif part:
                parts[part][option] = now
            elif now is None:
                into.pop(option, None)
            else:
                into[option] = now


def table_default(table: dict, key: str):
    """The catalogue's default of body option ``key`` (a world cannot leave one out)."""
    from sim_plant import catalogue

    return catalogue.bodies()[table["body"]].defaults()[key]


def _plain(value):
    """TOML's lists as lists (0.1's defaults were tuples)."""
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _budgets(budgets: dict, kind: Kind, table: dict, renames: dict) -> dict:
    """Budget keys to change: a source renamed; ``"plant.<option>"`` (0.1's figure of the
    kind) as the number it is now, or left out where the part driving the source has it."""
    changes = {}
    for name, spec in budgets.items():
        if not isinstance(spec, dict):
            continue
        change = {}
        for key in ("source", "ready"):
            if spec.get(key) in renames:
                change[key] = renames[spec[key]]
        if isinstance(spec.get("sources"), list) and any(s in renames for s in spec["sources"]):
            change["sources"] = [renames.get(s, s) for s in spec["sources"]]
        for key, value in spec.items():
            if not (isinstance(value, str) and value.startswith("plant.")):
                continue
            option = value.removeprefix("plant.")
            number = _figure(kind, table, option, spec.get("source"))
            if number is _NO_FIGURE:
                raise MigrationError(f"[budgets.{name}] {key}: {value!r} has no figure today: give it in microseconds")
            change[key] = number
        if change:
            changes[name] = change
    return changes


_NO_FIGURE = object()


def _figure(kind: Kind, table: dict, option: str, source) -> object:
    """0.1's ``plant.<option>`` now: None (left out) when the part that drives ``source``
    has it as its ``period_us``, else its value in the table; _NO_FIGURE when none."""
    parts = {p["name"]: p for p in table["parts"]}
    if option in kind.places:
        keys = kind.places[option](kind.defaults[option], option)
        for key, _ in keys:
            part, _, opt = key.rpartition(".")
            if part in parts:
                if opt == "period_us" and isinstance(source, str) and source.startswith(f"{part}."):
                    return None
                return parts[part].get(opt, kind.defaults[option])
    if option == "sonar_period_us":  # (the pool cleaner's: on each sonar part)
        sonar = next((p for p in table["parts"] if p["kind"] == "echo_sounder"), None)
        if sonar is not None and isinstance(source, str) and source.startswith(f"{sonar['name']}."):
            return None
    return _NO_FIGURE


# -- a rig file's text ----------------------------------------------------------------------

_HEADER = re.compile(r"^\s*(\[\[?)([^\]#]+?)(\]\]?)\s*(#.*)?$")


def _header_path(line: str) -> tuple | None:
    """A table header's key path (``[budgets."sonar.period"]`` -> ("budgets", "sonar.period"))."""
    match = _HEADER.match(line)
    if not match:
        return None
    try:
        data = tomllib.loads(f"[{match.group(2)}]")
    except tomllib.TOMLDecodeError:
        return None
    path = []
    while isinstance(data, dict) and len(data) == 1:
        key = next(iter(data))
        path.append(key)
        data = data[key]
    return tuple(path)


def plant_text(m: Migrated) -> str:
    lines = [f'[plant]                 # 0.1\'s kind = "{m.kind}" as a body and parts (docs/parts.md)']
    lines += [f"{toml_key(k)} = {toml_value(v)}" for k, v in m.plant.items() if k != "parts" and v is not None]
    for part in m.plant["parts"]:
        lines += ["", "[[plant.parts]]"]
        lines += [f"{toml_key(k)} = {toml_value(v)}" for k, v in part.items()]
    return "\n".join(lines) + "\n"


def migrate_text(text: str) -> tuple[str, Migrated]:
    """A 0.1 rig file's text in today's form (what is not the plant's as it was: the
    worlds' options, renamed signals, budget figures, ``console_baud``); the rest of the
    file, comments included, as it was."""
    data = tomllib.loads(text)
    if not is_01(data):
        raise MigrationError("[plant]: expected 0.1's [plant] kind (this file has a body, or no [plant])")
    m = migrate(data)
    lines = text.splitlines(keepends=True)
    sections: list[tuple[tuple | None, list[str]]] = [(None, [])]
    for line in lines:
        path = _header_path(line)
        if path is not None:
            sections.append((path, [line]))
        else:
            sections[-1][1].append(line)
    out, board_done = [], not isinstance(data.get("board"), dict) or "console_baud" in data["board"]
    for path, body in sections:
        if path == ("plant",):
            out.append(plant_text(m) + _trailing(body))
        elif path == ("plant", "options"):
            n = _tail(body)
            out.append("".join(line for line in body[len(body) - n :] if line.strip()))  # (its comments after)
        elif path and path[0] == "worlds" and len(path) == 2:
            values = "".join(f"{toml_key(k)} = {toml_value(v)}\n" for k, v in m.worlds[path[1]].items())
            out.append(body[0] + values + _trailing(body))
        elif path == ("wiring",):
            out.append("".join(_renamed(line, m.renames) for line in body))
        elif path and path[0] == "budgets" and len(path) == 2 and path[1] in m.budgets:
            out.append("".join(_budget_line(line, m.budgets[path[1]]) for line in body))
        elif path in (("board",), ("board", "pins")) and not board_done:
            note = 'console_baud = 0        # 0.1 printed for free (docs/shim.md, "Printing takes time")\n'
            if path == ("board",):
                n = _tail(body)
                out.append("".join(body[: len(body) - n]) + note + "".join(body[len(body) - n :]))
            else:
                out.append("[board]\n" + note + "\n" + "".join(body))
            board_done = True
        else:
            out.append("".join(body))
    return "".join(out).rstrip("\n") + "\n", m


def _tail(body: list) -> int:
    """How many lines end a section as blank lines and comments (they belong before the next)."""
    n = 0
    for line in reversed(body[1:]):
        if line.strip() and not line.lstrip().startswith("#"):
            break
        n += 1
    return n


def _trailing(body: list) -> str:
    n = _tail(body)
    return "".join(body[len(body) - n :]) if n else "\n"


_ASSIGN = re.compile(r'^(\s*(?:"[^"]*"|[A-Za-z0-9_-]+)\s*=\s*)"([^"]*)"(.*)$', re.S)


def _renamed(line: str, renames: dict) -> str:
    match = _ASSIGN.match(line)
    if not match or match.group(2) not in renames:
        return line
    return f'{match.group(1)}"{renames[match.group(2)]}"{match.group(3)}'


def _budget_line(line: str, change: dict) -> str:
    match = re.match(r"^\s*([A-Za-z0-9_-]+)\s*=\s*(.*)$", line, re.S)
    if not match or match.group(1) not in change:
        return line
    new = change[match.group(1)]
    if new is None:
        return ""  # (the part that drives the source has the period)
    comment = line.rstrip("\n").partition("#")[2]
    tail = f"   # {comment.strip()}" if comment and not isinstance(new, (int, float)) else ""
    return f"{match.group(1)} = {toml_value(new)}{tail}\n"


def migrated_path(path) -> Path:
    """Where ``mpy-fil migrate`` writes by default: beside the file (its paths are relative
    to its folder), ``rig.migrated.toml`` for ``rig.toml``."""
    path = Path(path)
    return path.with_name(f"{path.stem}.migrated.toml")


def message(data: dict, path) -> str:
    """load_rig's one message for a 0.1 rig file (after ``[plant] kind: ``): what the file
    is, its plant's form today and the command that writes it."""
    kind = data["plant"].get("kind")
    head = f"kind = {str(kind)[:60]!r} is 0.1's form; since 0.3 a plant is a body and parts"
    try:
        m = migrate(data)
    except MigrationError as e:
        return f"{head}, and this one cannot be written so by itself: {e}"
    renamed = ", ".join(f"{a} is {b}" for a, b in m.renames.items())
    return (
        f"{head}: here {m.summary()}" + (f" (signals renamed: {renamed})" if renamed else "") +
        f"; `mpy-fil migrate {path}` writes it as {migrated_path(path).name} (docs/rig-file.md, \"From 0.1\")"
    )  # fmt: skip
