"""The catalogue's parts in a plant: each does what its declaration says."""

import math

import pytest

from sim_plant.catalogue.assembly import assemble

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]


def robot(*parts, **body):
    return assemble({"body": "differential", **body, "parts": [*MOTORS, *parts]})


def drive(plant, duty_u16=65535, forward=True):
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", int(forward))
        plant.set_input(f"motor_{side}.in2", int(not forward))
        plant.set_input(f"motor_{side}.pwm", duty_u16)


def ping(plant, name, t_us):
    plant.advance_to(t_us)
    plant.set_input(f"{name}.trig", 1)
    plant.advance_to(t_us + 10)
    plant.set_input(f"{name}.trig", 0)
    edges = [c for c in plant.advance_to(t_us + 40_000) if c.name == f"{name}.echo"]
    return edges[1].t_us - edges[0].t_us


def test_dc_motor_lags_with_its_40_ms_default_and_polarity_reverses_it():
    plant = robot()
    drive(plant)
    plant.advance_to(40_000)
    v_40ms = plant.truth()["v_m_s"]
    plant.advance_to(400_000)
    assert v_40ms == pytest.approx(0.4 * (1 - math.exp(-1)), rel=0.1), "one time constant: 63 %"
    assert plant.truth()["v_m_s"] == pytest.approx(0.4, rel=0.01)
    flipped = assemble({"body": "differential", "parts": [MOTORS[0], {**MOTORS[1], "polarity": -1}]})
    drive(flipped)
    flipped.advance_to(400_000)
    assert flipped.truth()["v_m_s"] == pytest.approx(0.0, abs=1e-9) and flipped.truth()["w_rad_s"] < -1


@pytest.mark.parametrize(
    ("bridge", "inputs"), [("drv8833", {"in1": "duty", "in2": "duty"}), ("dir_pwm", {"dir": "level", "pwm": "duty"})]
)
def test_dc_motor_bridges_give_their_pins(bridge, inputs):
    plant = assemble({"body": "differential", "parts": [{**m, "bridge": bridge} for m in MOTORS]})
    assert {k: v for k, v in plant.inputs.items() if k.startswith("motor_l.")} == {
        f"motor_l.{k}": v for k, v in inputs.items()
    }


def test_dc_motor_rpm_through_its_gearbox_sets_the_speed():
    plant = assemble(
        {"body": "differential", "parts": [{**m, "rpm": 6000, "gear_ratio": 30, "time_constant_ms": 0} for m in MOTORS]}
    )
    drive(plant)
    plant.advance_to(10_000)
    assert plant.truth()["v_m_s"] == pytest.approx(6000 / 30 / 60 * 2 * math.pi * 0.0325)


@pytest.mark.parametrize(("on", "edges_per_wheel_rev"), [("wheel", 4 * 12), ("motor", 4 * 12 * 30)])
def test_encoder_on_the_wheel_or_the_motor_shaft(on, edges_per_wheel_rev):
    enc = {"kind": "encoder", "name": "e", "on": on, "gear_ratio": 30, "lines_per_rev": 12}
    plant = robot(enc, {"kind": "encoder", "name": "s", "channels": "single", "wheel": "right", "polarity": -1})
    drive(plant)
    plant.advance_to(2_000_000)
    turns = plant.truth()["wheel_rad_s"][0] * 2 / (2 * math.pi)  # about: the lag's first 40 ms aside
    assert plant.truth()["e_edges"] == pytest.approx(turns * edges_per_wheel_rev, rel=0.05)
    assert plant.truth()["s_edges"] < 0 and "s.out" in plant.outputs


def test_a_front_and_a_rear_hcsr04_each_see_their_own_wall():
    front = {"kind": "hcsr04", "name": "front", "mount": {"x_m": 0.08}, "noise_sd_m": 0}
    rear = {"kind": "hcsr04", "name": "rear", "mount": {"x_m": -0.08, "heading_deg": 180}, "noise_sd_m": 0}
    plant = robot(front, rear, start_pose=[1.0, 1.0, 0.0])
    width_front = ping(plant, "front", 1_000)
    width_rear = ping(plant, "rear", 100_000)
    assert width_front / 58.31 == pytest.approx(192, abs=1)  # 3.0 - 1.08 m
    assert width_rear / 58.31 == pytest.approx(92, abs=1)  # 1.0 - 0.08 m
    truth = plant.truth()
    assert truth["front_ping_range_m"] == pytest.approx(1.92) and truth["rear_ping_range_m"] == pytest.approx(0.92)


def test_analog_ranger_reads_its_range_on_the_adc():
    plant = robot(
        {"kind": "analog_ranger", "name": "r", "noise_sd_m": 0, "period_us": 10_000}, start_pose=[2.0, 1.0, 0.0]
    )
    last = [c for c in plant.advance_to(30_000) if c.name == "r.adc"][-1]
    volts = last.value / 65535 * 3.3
    assert volts / 0.2538 == pytest.approx(1.0, abs=0.01) and plant.truth()["r_range_m"] == pytest.approx(1.0)


def test_a_rear_bumper_closes_when_the_robot_backs_into_the_wall():
    bumper = {"kind": "bumper", "name": "back", "mount": {"heading_deg": 180}, "active_low": False}
    plant = robot(bumper, start_pose=[0.3, 1.0, 0.0])
    assert plant.output("back.out") == 0
    drive(plant, forward=False)
    changes = [c for c in plant.advance_to(2_000_000) if c.name == "back.out"]
    assert [c.value for c in changes] == [1]
    assert plant.truth()["back.out_pressed"] and plant.truth()["contacts"][0].part == "back.out"


@pytest.mark.parametrize(("active_low", "levels"), [(True, [1, 0, 1]), (False, [0, 1, 0])])
def test_a_button_is_active_low_or_high_at_its_scheduled_times(active_low, levels):
    plant = assemble(
        {"body": "bench", "parts": [{"kind": "button", "name": "b", "active_low": active_low, "presses": [[0.5, 0.7]]}]}
    )
    assert plant.output("b.out") == levels[0]
    changes = plant.advance_to(1_000_000)
    assert [(c.t_us, c.value) for c in changes] == [(500_000, levels[1]), (700_000, levels[2])]


def test_line_sensors_digital_array_sees_the_tape_under_one_of_them():
    sensors = {
        "kind": "line_sensor",
        "name": "line",
        "output": "digital",
        "offsets_m": [[0, 0.02], [0, -0.02]],
        "mount": {"x_m": 0.05},
    }
    plant = robot(sensors, start_pose=[1.0, 1.0, 0.0], tape=[[0.0, 1.02], [3.0, 1.02]], tape_width_m=0.01)
    assert plant.outputs["line.0"] == "level"
    assert (plant.output("line.0"), plant.output("line.1")) == (1, 0)
    assert plant.truth()["line_on_tape"] == [True, False]


def test_battery_drains_with_the_motors_and_reads_through_its_divider():
    battery = {"kind": "battery", "name": "bat", "motor_drain_v_per_s": 0.1, "period_us": 100_000}
    plant = robot(battery)
    assert plant.output("bat.adc") / 65535 * 3.3 == pytest.approx(8.4 / 3, abs=0.01)
    plant.advance_to(1_000_000)
    assert plant.truth()["bat_v"] == 8.4, "no drain while the motors are off"
    drive(plant)
    plant.advance_to(11_000_000)
    assert plant.truth()["bat_v"] == pytest.approx(8.4 - 1.0, abs=0.02)


def test_a_probe_records_what_the_board_drives():
    plant = assemble(
        {
            "body": "bench",
            "parts": [{"kind": "probe", "name": "led"}, {"kind": "probe", "name": "fan", "signal": "duty"}],
        }
    )
    for value in (1, 0, 1):
        plant.set_input("led.in", value)
    plant.set_input("fan.in", 30000)
    truth = plant.truth()
    assert (truth["led_value"], truth["led_changes"], truth["fan_value"]) == (1, 3, 30000)
    assert plant.inputs == {"led.in": "level", "fan.in": "duty"}
