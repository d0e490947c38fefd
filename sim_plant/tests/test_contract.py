"""Every plant keeps the contract of sim_plant.plant: outputs as electrical signals, changes
in time order and never before next_change_us() says, the same changes however the time is
cut, the same seed the same run, and snapshots that replay the same future."""

import random
from pathlib import Path

import pytest

from sim_plant.catalogue.assembly import assemble, assemble_file, rig_plant_table
from sim_plant.plant import NEVER_US
from sim_plant.tests.rigs import duct_robot, pool_cleaner

APPS = Path(__file__).resolve().parents[2] / "firmware" / "apps"
MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]


def with_parts(rig_file, *parts):
    """The plant of one of our rig files with ``parts`` added."""
    table = rig_plant_table(rig_file)
    return assemble({**table, "parts": [*table["parts"], *parts]})


PLANTS = {
    "rover": lambda: assemble_file(APPS / "rover" / "rig.toml", room_w_m=3.0, room_h_m=3.0, start_pose=[1.5, 1.5, 0.0]),
    "pool_nmea": lambda: pool_cleaner(pool_length_m=4.0, start_pose=(2.0, 3.0, 0.2), reversal_pause_ms=300),
    "pool_adc": lambda: pool_cleaner(
        "rig-adc.toml",
        pool_length_m=4.0,
        start_pose=(2.0, 3.0, 0.0),
        **{"bumper_front.bounce_us": 800, "bumper_rear.bounce_us": 800},
    ),
    "pool_faults": lambda: pool_cleaner(
        pool_length_m=4.0,
        start_pose=(2.0, 3.0, 0.1),
        **{"sonar.faults": [(1.0, 3.0, "wrong"), (3.5, 5.0, "silent"), (6.0, 7.0, "none")]},
    ),
    "duct": lambda: duct_robot(
        "multi_branch_duct",
        extra_parts=[{"kind": "bumper", "name": "bumper", "half_arc_deg": 60}],
        **{"motor_l.time_constant_ms": 30.0, "motor_r.time_constant_ms": 30.0},
    ),
    "vacuum": lambda: with_parts(APPS / "vacuum" / "rig.toml", {"kind": "bumper", "name": "bumper", "bounce_us": 1500}),
    "lab": lambda: with_parts(APPS / "lab_robot" / "rig-canyon.toml", {"kind": "bumper", "name": "bumper"}),
    "differential": lambda: assemble(
        {
            "body": "differential",
            "obstacles": [[2.0, 1.0, 0.3, 0.3]],
            "parts": [
                *MOTORS,
                {"kind": "standby", "name": "motor"},
                {"kind": "encoder", "name": "enc_l", "wheel": "left"},
                {"kind": "encoder", "name": "enc_r", "wheel": "right"},
                {"kind": "bumper", "name": "bumper"},
                {"kind": "hcsr04", "name": "sonar", "mount": {"x_m": 0.08}},
                {"kind": "placement", "name": "box1", "t_s": 1.5, "box": [1.0, 1.4, 0.2, 0.2]},
                {"kind": "placement", "name": "box2", "t_s": 4.0, "box": [0.5, 0.5, 0.2, 0.2]},
                {"kind": "button", "name": "go", "presses": [[0.5, 0.7], [3.0, 3.1]]},
            ],
        }
    ),
    "differential_drv8833": lambda: assemble(
        {
            "body": "differential",
            "tape": [[0.5, 0.3], [2.5, 1.7], [0.5, 1.7]],
            "parts": [
                {"kind": "dc_motor", "name": "motor_l", "drives": "left", "bridge": "drv8833"},
                {"kind": "dc_motor", "name": "motor_r", "drives": "right", "bridge": "drv8833"},
                {"kind": "encoder", "name": "enc_l", "wheel": "left", "channels": "single"},
                {"kind": "encoder", "name": "enc_r", "wheel": "right", "channels": "single"},
                {"kind": "analog_ranger", "name": "ranger", "mount": {"x_m": 0.08}},
                {"kind": "line_sensor", "name": "floor", "offsets_m": [[0.06, -0.01], [0.06, 0.01]]},
                {"kind": "button", "name": "a", "presses": [[1.0, 1.5]], "bounce_us": 3_000},
            ],
        }
    ),
}
END_US = 8_000_000


def schedule(plant, seed):
    """Random actuator writes, as a firmware would make them: (t_us, name, value)."""
    rnd = random.Random(seed)
    events, t = [], 0
    while t < END_US:
        t += rnd.randrange(1_000, 120_000)
        name = rnd.choice(sorted(plant.inputs))
        kind = plant.inputs[name]
        if kind == "duty":
            value = rnd.choice((0, 20_000, 40_000, 65535, rnd.randrange(65536)))
        else:
            value = rnd.randrange(2)
        events.append((t, name, value))
        if name == "sonar.trig" and value == 1:  # a proper 10 us trigger pulse
            events.append((t + 12, name, 0))
            t += 12
    return events


def run(plant, events, *, host_loop: bool, chunk_seed: int = 0, limit_seed: int | None = None):
    """Apply the writes at their times; advance event by event (as the host does), in
    random chunks, or (``limit_seed``) to each write with random change limits. Checks
    the contract on the way; returns all changes."""
    rnd = random.Random(chunk_seed if limit_seed is None else limit_seed)
    changes = []
    pending = list(events) + [(END_US, None, None)]
    for t_write, name, value in pending:
        while plant.t_us < t_write:
            before = plant.t_us
            nxt = plant.next_change_us()
            assert nxt > before
            if limit_seed is not None:
                target, limit = t_write, rnd.randrange(1, 6)
                got = plant.advance_to(target, limit)
                if plant.t_us < target:
                    assert len(got) >= limit, "stopped early without reaching the limit"
                    assert got[-1].t_us == plant.t_us, "stopped anywhere but at its last change"
                    assert plant.next_change_us() > plant.t_us
                    target = plant.t_us
                else:
                    assert plant.t_us == target
            else:
                if host_loop:
                    target = min(nxt, t_write)
                else:
                    target = min(before + rnd.randrange(1, 400_000), t_write)
                got = plant.advance_to(target)
                assert plant.t_us == target
            for c in got:
                assert before < c.t_us <= target
                assert c.t_us >= nxt, "a change came before next_change_us() said"
            assert [c.t_us for c in got] == sorted(c.t_us for c in got)
            changes += got
        if name is not None:
            plant.set_input(name, value)
    return changes


@pytest.mark.parametrize("kind", sorted(PLANTS))
def test_changes_do_not_depend_on_how_time_is_cut(kind):
    a, b = PLANTS[kind](), PLANTS[kind]()
    a.reset(11)
    b.reset(11)
    events = schedule(a, 5)
    c = PLANTS[kind]()
    c.reset(11)
    by_event = run(a, events, host_loop=True)
    by_chunk = run(b, events, host_loop=False, chunk_seed=3)
    by_limit = run(c, events, host_loop=False, limit_seed=7)
    assert len(by_event) > 20
    assert by_event == by_chunk == by_limit
    assert a.truth() == b.truth() == c.truth()


@pytest.mark.parametrize("kind", sorted(PLANTS))
def test_outputs_are_signals_of_their_declared_kind(kind):
    plant = PLANTS[kind]()
    plant.reset(2)
    last = {name: plant.output(name) for name in plant.outputs}
    for c in run(plant, schedule(plant, 8), host_loop=False, chunk_seed=1):
        kind_ = plant.outputs[c.name]
        if kind_ == "level":
            assert c.value in (0, 1) and c.value != last[c.name], f"{c.name}: a level change must flip"
        elif kind_ == "u16":
            assert isinstance(c.value, int) and 0 <= c.value <= 65535
        else:
            assert kind_ == "bytes" and isinstance(c.value, bytes) and c.value
        last[c.name] = c.value
    for name, value in last.items():
        if plant.outputs[name] != "bytes":
            assert plant.output(name) == value


@pytest.mark.parametrize("kind", sorted(PLANTS))
def test_same_seed_same_run_other_seed_other_run(kind):
    runs = []
    for seed in (4, 4, 5):
        plant = PLANTS[kind]()
        plant.reset(seed)
        runs.append(run(plant, schedule(plant, 9), host_loop=False))
    assert runs[0] == runs[1]
    assert runs[0] != runs[2]


@pytest.mark.parametrize("kind", sorted(PLANTS))
def test_snapshot_restore_replays_the_same_future(kind):
    plant = PLANTS[kind]()
    plant.reset(6)
    events = schedule(plant, 10)
    head = [e for e in events if e[0] < 3_000_000]
    tail = [e for e in events if e[0] >= 3_000_000]
    run_to = [*head, (3_000_000, None, None)]
    for t, name, value in run_to:
        plant.advance_to(t)
        if name:
            plant.set_input(name, value)
    snap = plant.snapshot()
    futures = []
    for _ in range(3):
        futures.append((run(plant, tail, host_loop=True), plant.truth()))
        plant.restore(snap)
        assert plant.t_us == 3_000_000
    assert futures[0] == futures[1] == futures[2]


def _fixed_state(plant):
    """What every object of the plant declares fixed (FIXED_STATE), copied."""
    import copy

    from sim_plant.engine import state_objects

    found = {}
    for obj in state_objects(plant):
        fixed = getattr(type(obj), "FIXED_STATE", ())
        for key, value in vars(obj).items():
            if fixed is True or key in fixed:
                found[(type(obj).__name__, id(obj), key)] = copy.copy(value)
    return found


@pytest.mark.parametrize("kind", sorted(PLANTS))
def test_state_declared_fixed_never_changes(kind):
    """Snapshots skip what a class declares fixed (FIXED_STATE): it must stay as built."""
    plant = PLANTS[kind]()
    plant.reset(3)
    before = _fixed_state(plant)
    assert before, f"{kind}: nothing declared fixed"
    run(plant, schedule(plant, 11), host_loop=True)
    after = _fixed_state(plant)
    assert after.keys() == before.keys()
    changed = [key for key in before if after[key] != before[key]]
    assert not changed, f"{kind}: declared fixed but changed during the run: {changed}"


def test_unknown_signals_are_refused_with_their_names():
    plant = pool_cleaner()
    with pytest.raises(KeyError, match="track_l.stop"):
        plant.set_input("motor_l.pwm", 1)
    with pytest.raises(KeyError, match="bumper_front.out"):
        plant.output("bumper")


def test_an_idle_plant_has_only_its_sensor_timeline():
    plant = duct_robot(**{f"sonar_{s}.noise_sd_v": 0.0 for s in "flr"})
    plant.advance_to(1_000_000)
    assert plant.next_change_us() == plant.t_us + 25_000  # the amplitude sonars' update
    quiet = assemble_file(APPS / "vacuum" / "rig.toml")
    assert quiet.next_change_us() == NEVER_US


def test_a_scripted_plant_stops_after_the_instant_that_reaches_the_limit():
    from sim_plant.scripted import ScriptedPlant

    plant = ScriptedPlant(
        [(10, "a", 1), (10, "b", 1), (20, "a", 0), (30, "b", 0)], outputs={"a": "level", "b": "level"}, inputs={}
    )
    first = plant.advance_to(100, limit=1)
    assert [(c.t_us, c.name) for c in first] == [(10, "a"), (10, "b")] and plant.t_us == 10
    assert [c.t_us for c in plant.advance_to(100, limit=5)] == [20, 30] and plant.t_us == 100
