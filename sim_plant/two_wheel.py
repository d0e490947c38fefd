"""A two-wheel robot assembled from common parts by options: what most hobby robots
are, described in a rig file without Python (``[plant] kind = "two_wheel"``).

The body is a disc with two driven wheels on its centre axis, in a rectangular room with
box obstacles. Each option picks a part:

==========================  ===============  ===============================================
option                      default          parts and the signals they add
==========================  ===============  ===============================================
``bridge``                  ``"tb6612"``     ``tb6612`` or ``l298n``: ``motor_l.in1``,
                                             ``motor_l.in2`` (levels), ``motor_l.pwm``
                                             (duty), the same for ``motor_r``; ``drv8833``:
                                             ``motor_l.in1``, ``motor_l.in2`` (both duty);
                                             ``dir_pwm``: ``motor_l.dir``, ``motor_l.pwm``
``standby``                 false            TB6612 STBY: a ``motor.stby`` input, low at
                                             reset (both channels off until it goes high)
``encoder``                 ``"quadrature"`` ``enc_l.a``, ``enc_l.b``, ``enc_r.a``,
                                             ``enc_r.b``; ``single``: ``enc_l``, ``enc_r``
                                             (a slotted disk); ``none``
``encoder_cpr``             7                lines (slots) per motor-shaft revolution
``gear_ratio``              20.0             motor turns per wheel turn
``encoder_polarity``        ``[1, 1]``       -1 counts a wheel backwards (a mirrored motor)
``ranger``                  ``"hcsr04"``     ``sonar.trig`` in, ``sonar.echo`` out, 58.31 us
                                             per cm; ``analog``: ``ranger.adc`` (u16, a new
                                             sample every ``ranger_period_us``); ``none``
``hcsr04_trigger_min_us``   2                shortest TRIG pulse the module answers
``bumper``                  true             ``bumper``, 0 while pressed (front 140 deg)
``buttons``                 ``[]``           names: an output ``button.<name>`` each, 1
                                             released, 0 pressed (a button to ground)
``presses``                 ``[]``           ``[name, t_press_s, t_release_s]`` each
``button_bounce_us``        0                contact chatter at each press and release
``line_sensors``            ``[]``           ``[dx, dy]`` offsets (m, body frame) of floor
                                             reflectance sensors: ``floor_0.adc``, ... (u16)
``tape``                    ``[]``           the tape's path, ``[x, y]`` points; ``tape_width_m``
                                             0.019; ``tape_u16`` 58000 over it, ``floor_u16``
                                             6000 off it; checked every ``floor_period_us`` 1000
``placements``              ``[]``           ``[t_s, cx, cy, w, h]``: a box placed at t_s
==========================  ===============  ===============================================

Geometry and drive: ``room_w_m`` x ``room_h_m`` (3 x 2), ``obstacles`` as
``[cx, cy, w, h]`` boxes, ``start_pose`` ``[x, y, theta]`` (0.4, 1.0, 0); or ``world``,
one of our worlds (``canyon``, ``duct``, ``multi_branch_duct``, ``vacuum_room``,
``pool``), each with a start pose of its own. ``body_radius_m`` 0.08, ``wheel_radius_m``
0.0325, ``track_m`` 0.15, ``v_max_m_s`` 0.4 (rim speed at full duty; or ``motor_rpm``,
the motor's no-load speed before the gearbox), ``deadband_duty`` 0.1, ``motor_gains``
[1, 1] (per-wheel mismatch), ``motor_time_constant_ms`` 0. The defaults are a typical
6 V N20 gear-motor robot, not a measured one (7 lines per motor turn: a Hall encoder on
a 1:20 N20 motor).
"""

import math

from sim_plant import world as worlds
from sim_plant.contacts import ContactMonitor, front_bumper
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.encoders import QuadratureEncoder, SlottedDiskEncoder
from sim_plant.engine import Part, RobotPlant
from sim_plant.hcsr04 import HcSr04
from sim_plant.motors import DirPinsPwmBridge, DirPwmBridge, TwoPwmBridge
from sim_plant.plant import NEVER_US, Change
from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, AnalogRangeSonar, BeamRangeModel
from sim_plant.world import box, room

WORLDS = {  # a named world instead of the room: (the world, where the robot starts)
    "canyon": (lambda: worlds.canyon(), (0.3, 0.0, 0.0)),
    "duct": (lambda: worlds.one_right_branch_duct(), (0.3, 0.2, 0.0)),
    "multi_branch_duct": (lambda: worlds.multi_branch_duct(), (0.3, 0.2, 0.0)),
    "vacuum_room": (lambda: worlds.vacuum_room(), (0.5, 0.5, 0.0)),
    "pool": (lambda: worlds.pool(), (1.0, 1.0, 0.0)),
}

BRIDGES = {
    "tb6612": DirPinsPwmBridge,
    "l298n": DirPinsPwmBridge,
    "drv8833": TwoPwmBridge,
    "dir_pwm": DirPwmBridge,
}
ENCODERS = ("quadrature", "single", "none")
RANGERS = ("hcsr04", "analog", "none")


class Buttons(Part):
    """Push-buttons to ground with a pull-up, pressed at scripted times. With
    ``bounce_us``, each press and release chatters: the new level, the old one a quarter
    of the way in, the new one again half way, as a worn contact does."""

    FIXED_STATE = ("events", "inputs", "outputs")

    def __init__(self, names, presses, bounce_us: int = 0):
        self.outputs = {f"button.{n}": "level" for n in names}
        events = []
        for name, t_press_s, t_release_s in presses:
            if name not in names:
                raise ValueError(f"presses: no button {name!r} (buttons: {', '.join(names) or 'none'})")
            if not 0 <= t_press_s < t_release_s:
                raise ValueError(f"presses: {name} pressed at {t_press_s} s, released at {t_release_s} s")
            for t_s, level in ((t_press_s, 0), (t_release_s, 1)):
                t_us = round(t_s * 1e6)
                events.append((t_us, f"button.{name}", level))
                if bounce_us > 0:
                    events.append((t_us + bounce_us // 4, f"button.{name}", 1 - level))
                    events.append((t_us + bounce_us // 2, f"button.{name}", level))
        self.events = sorted(events)
        self.i = 0
        self.next_us = self.events[0][0] if self.events else NEVER_US

    def initial_outputs(self) -> dict:
        return dict.fromkeys(self.outputs, 1)

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.i < len(self.events) and self.events[self.i][0] <= t_us:
            _t, name, level = self.events[self.i]
            out.append(Change(t_us, name, level))
            self.i += 1
        self.next_us = self.events[self.i][0] if self.i < len(self.events) else NEVER_US


class FloorSensors(Part):
    """Reflectance sensors looking at the floor (TCRT5000 or QTR style, on an ADC): each
    reads ``tape_u16`` over the tape (dark: little light comes back, the output is high)
    and ``floor_u16`` elsewhere. The floor is checked every ``period_us``; a reading is a
    change only when it flips (a continuous voltage, not a sampled one)."""

    FIXED_STATE = ("offsets", "tape", "inputs", "outputs", "names")

    def __init__(self, offsets, tape, *, width_m, tape_u16, floor_u16, period_us):
        if period_us <= 0:
            raise ValueError(f"floor_period_us: expected > 0, got {period_us}")
        if len(tape) == 1 or any(len(p) != 2 for p in tape):
            raise ValueError("tape: expected a path of [x, y] points (two or more)")
        self.offsets = [tuple(float(v) for v in o) for o in offsets]
        self.tape = [tuple(float(v) for v in p) for p in tape]
        self.half_width_m = float(width_m) / 2
        self.levels = (int(floor_u16), int(tape_u16))
        self.period_us = int(period_us)
        self.names = [f"floor_{i}.adc" for i in range(len(self.offsets))]
        self.outputs = dict.fromkeys(self.names, "u16")
        self.values = [self.levels[0]] * len(self.offsets)
        self.next_us = NEVER_US

    def start(self, t_us: int, plant) -> None:
        self.values = self._read(plant.pose_at(t_us))
        self.next_us = t_us + self.period_us

    def initial_outputs(self) -> dict:
        return dict(zip(self.names, self.values))

    def fire(self, t_us: int, plant, out: list) -> None:
        for name, old, new in zip(self.names, self.values, self._read(plant.pose_at(t_us))):
            if new != old:
                out.append(Change(t_us, name, new))
        self.values = self._read(plant.pose_at(t_us))
        self.next_us = t_us + self.period_us

    def _read(self, pose) -> list[int]:
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)
        return [self.levels[self._on_tape(x + dx * c - dy * s, y + dx * s + dy * c)] for dx, dy in self.offsets]

    def _on_tape(self, px: float, py: float) -> bool:
        for (ax, ay), (bx, by) in zip(self.tape, self.tape[1:]):
            ux, uy = bx - ax, by - ay
            k = max(0.0, min(1.0, ((px - ax) * ux + (py - ay) * uy) / (ux * ux + uy * uy or 1.0)))
            if math.hypot(px - ax - k * ux, py - ay - k * uy) <= self.half_width_m:
                return True
        return False


class Placements(Part):
    """Boxes placed in the room at scripted times (a door closing, a chair pushed in the
    way): at each time the world gains the box and the contacts are checked at once."""

    FIXED_STATE = ("events", "inputs", "outputs")

    def __init__(self, events):
        self.events = sorted((round(t_s * 1e6), tuple(float(v) for v in b)) for t_s, *b in events)
        self.i = 0
        self.next_us = self.events[0][0] if self.events else NEVER_US

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.i < len(self.events) and self.events[self.i][0] <= t_us:
            self.i += 1
        placed = [b for _t, b in self.events[: self.i]]
        plant.world = room(plant.room_w_m, plant.room_h_m, [box(*b) for b in [*plant.obstacles, *placed]], name="room")
        plant.part(ContactMonitor).recheck(t_us)
        self.next_us = self.events[self.i][0] if self.i < len(self.events) else NEVER_US


class TwoWheelRobot(RobotPlant):
    def __init__(
        self,
        *,
        world="room",
        room_w_m=3.0,
        room_h_m=2.0,
        obstacles=(),
        start_pose=None,
        body_radius_m=0.08,
        wheel_radius_m=0.0325,
        track_m=0.15,
        v_max_m_s=0.4,
        motor_rpm=None,
        deadband_duty=0.1,
        motor_gains=(1.0, 1.0),
        motor_time_constant_ms=0.0,
        bridge="tb6612",
        standby=False,
        encoder="quadrature",
        encoder_cpr=7,
        gear_ratio=20.0,
        encoder_polarity=(1, 1),
        ranger="hcsr04",
        ranger_noise_sd_m=0.003,
        hcsr04_trigger_min_us=2,
        ranger_period_us=50_000,
        bumper=True,
        bumper_bounce_us=0,
        buttons=(),
        presses=(),
        button_bounce_us=0,
        line_sensors=(),
        tape=(),
        tape_width_m=0.019,
        tape_u16=58_000,
        floor_u16=6_000,
        floor_period_us=1_000,
        placements=(),
    ):
        _choice("bridge", bridge, BRIDGES)
        _choice("encoder", encoder, ENCODERS)
        _choice("ranger", ranger, RANGERS)
        if standby and bridge != "tb6612":
            raise ValueError(f"standby: only the tb6612 has a STBY pin, not the {bridge}")
        self.room_w_m, self.room_h_m = float(room_w_m), float(room_h_m)
        self.body_radius_m = float(body_radius_m)
        for name, size in (("room_w_m", self.room_w_m), ("room_h_m", self.room_h_m)):
            if not size > 2 * self.body_radius_m:
                raise ValueError(f"{name}: expected a room wider than the robot, got {size:g}")
        if world != "room" and world not in WORLDS:
            raise ValueError(f"world: expected room or one of {', '.join(WORLDS)}, got {world!r}")
        self.world_name = world
        self.obstacles = [tuple(float(v) for v in o) for o in obstacles]
        if any(len(o) != 4 for o in self.obstacles):
            raise ValueError("obstacles: expected [cx, cy, w, h] boxes")
        if world == "room":
            start_pose = (0.4, 1.0, 0.0) if start_pose is None else start_pose
            x, y, _th = start_pose
            if not (self.body_radius_m <= x <= self.room_w_m - self.body_radius_m and 0 < y < self.room_h_m):
                raise ValueError(f"start_pose: {list(start_pose)} puts the robot outside the room")
            self.world = self._base_world()

        else:
            if obstacles or placements:
                raise ValueError(f"obstacles, placements: only in the room world, not in {world}")
            start_pose = WORLDS[world][1] if start_pose is None else start_pose
            self.world = self._base_world()
        if motor_rpm is not None:  # the motor's no-load speed through the gearbox
            v_max_m_s = float(motor_rpm) / float(gear_ratio) * 2 * math.pi * float(wheel_radius_m) / 60
        self._set_wheels(
            start_pose=start_pose,
            wheel_radius_m=wheel_radius_m,
            track_m=track_m,
            v_max_m_s=v_max_m_s,
            deadband_duty=deadband_duty,
            motor_gains=motor_gains,
            motor_time_constant_ms=motor_time_constant_ms,
            bumper=bumper,
            bumper_bounce_us=bumper_bounce_us,
        )
        self.bridge, self.standby, self.encoder, self.ranger = bridge, bool(standby), encoder, ranger
        self.encoder_cpr, self.gear_ratio = int(encoder_cpr), float(gear_ratio)
        self.encoder_polarity = tuple(int(p) for p in encoder_polarity)
        self.ranger_noise_sd_m = float(ranger_noise_sd_m)
        self.hcsr04_trigger_min_us = int(hcsr04_trigger_min_us)
        self.ranger_period_us = int(ranger_period_us)
        self.floor_period_us = int(floor_period_us)
        self.buttons = tuple(buttons)
        self.presses = tuple(tuple(p) for p in presses)
        self.button_bounce_us = int(button_bounce_us)
        Buttons(self.buttons, self.presses, self.button_bounce_us)  # refuse bad presses now
        self.line_sensors = tuple(tuple(o) for o in line_sensors)
        self.tape = tuple(tuple(p) for p in tape)
        self.floor_options = {
            "width_m": tape_width_m,
            "tape_u16": tape_u16,
            "floor_u16": floor_u16,
            "period_us": self.floor_period_us,
        }
        if self.line_sensors:
            FloorSensors(self.line_sensors, self.tape, **self.floor_options)  # refuse bad options now
        self.placements = tuple(tuple(p) for p in placements)
        if any(len(p) != 5 or p[0] < 0 for p in self.placements):
            raise ValueError("placements: expected [t_s, cx, cy, w, h] boxes, t_s >= 0")
        super().__init__()

    def _build(self) -> None:
        make = BRIDGES[self.bridge]
        self.drive = DiffDriveTrain(
            bridges=(make("motor_l"), make("motor_r")),
            motors=self._wheel_motors(),
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
            standby="motor.stby" if self.standby else None,
        )
        self.encoders = []
        for wheel, side in enumerate("lr"):
            pol = self.encoder_polarity[wheel]
            opts = {"wheel": wheel, "lines_per_rev": self.encoder_cpr, "gear_ratio": self.gear_ratio, "polarity": pol}
            if self.encoder == "quadrature":
                self.encoders.append(QuadratureEncoder((f"enc_{side}.a", f"enc_{side}.b"), **opts))
            elif self.encoder == "single":
                self.encoders.append(SlottedDiskEncoder((f"enc_{side}",), **opts))
        bumpers = [front_bumper(70.0, self.bumper_bounce_us)] if self.bumper else []
        self.parts = [ContactMonitor([(0.0, 0.0, self.body_radius_m)], bumpers)]
        mount = (self.body_radius_m, 0.0, 0.0)
        if self.ranger == "hcsr04":
            ranger = HcSr04(mount=mount, noise_sd_m=self.ranger_noise_sd_m, trigger_min_us=self.hcsr04_trigger_min_us)
            self.parts.append(ranger)
        elif self.ranger == "analog":
            model = BeamRangeModel(
                noise_sd_m=self.ranger_noise_sd_m, min_m=0.03, max_m=4.0, offset_m=self.body_radius_m
            )
            sonar = AnalogRangeSonar(
                "ranger.adc", model, period_us=self.ranger_period_us, volts_per_m=MAXBOTIX_V_PER_M, adc=Adc(12, 3.3)
            )
            self.parts.append(sonar)
        if self.buttons:
            self.parts.append(Buttons(self.buttons, self.presses, self.button_bounce_us))
        if self.line_sensors:
            self.parts.append(FloorSensors(self.line_sensors, self.tape, **self.floor_options))
        if self.placements:
            self.parts.append(Placements(self.placements))
            self.world = self._base_world()  # (placed boxes are gone at a reset)

    def _base_world(self):
        if self.world_name != "room":
            return WORLDS[self.world_name][0]()
        return room(self.room_w_m, self.room_h_m, [box(*o) for o in self.obstacles], name="room")

    def truth(self) -> dict:
        truth = super().truth()
        truth["heading_deg"] = math.degrees(truth["theta_rad"])
        return truth


def _choice(name: str, value, choices) -> None:
    if value not in choices:
        raise ValueError(f"{name}: expected one of {', '.join(choices)}, got {value!r}")
