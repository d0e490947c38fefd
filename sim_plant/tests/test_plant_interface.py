"""The plant's interface (sim_plant/plant.py): what every plant answers has a default, what
only some can do is a declared capability, checked when a plant class is made and when a
plant is built; the fault wrapper answers for the plant inside it (``unwrapped``)."""

import inspect

import pytest

from sim_plant.catalogue.assembly import assemble_file
from sim_plant.faults import parse_faults, with_faults
from sim_plant.plant import BUSES, CAPABILITIES, POSE, PWM, ContractError, Plant, check_contract
from sim_plant.scripted import ScriptedPlant
from sim_plant.tests.test_contract import APPS

STUCK = [{"kind": "stuck", "signal": "bumper.out", "value": 1, "start_s": 1, "end_s": 2}]


def test_a_class_with_a_capabilitys_methods_must_declare_it_and_the_other_way_round():
    with pytest.raises(ContractError, match="implements set_pwm but does not declare 'pwm'"):

        class Undeclared(ScriptedPlant):
            def set_pwm(self, name, freq_hz, duty_u16):
                pass

    with pytest.raises(ContractError, match="declares 'buses' but does not implement bus_transfer"):

        class Claimed(ScriptedPlant):
            capabilities = frozenset((BUSES,))

    class Pwm(ScriptedPlant):
        capabilities = frozenset((PWM,))

        def set_pwm(self, name, freq_hz, duty_u16):
            self.pwm = (name, freq_hz, duty_u16)

    plant = check_contract(Pwm(outputs={}, inputs={"led.in": "pwm"}))
    plant.set_pwm("led.in", 1000, 100)
    assert plant.pwm == ("led.in", 1000, 100)


def test_a_plant_is_refused_when_built_with_an_input_its_capabilities_cannot_take():
    with pytest.raises(ContractError, match=r"input 'w0\.in' is of kind 'pwm', which needs the 'pwm' capability"):
        check_contract(ScriptedPlant(outputs={}, inputs={"w0.in": "pwm"}))
    plant = ScriptedPlant(outputs={"x": "level"}, inputs={"y": "level"})
    assert check_contract(plant) is plant
    plant.capabilities = frozenset(("wings",))
    with pytest.raises(ContractError, match="unknown capability 'wings'"):
        check_contract(plant)


def test_every_plant_answers_the_interface_with_safe_defaults():
    plant = ScriptedPlant(outputs={"x": "level"}, inputs={})
    assert plant.unwrapped is plant and plant.fault_schedule == () and plant.capabilities == frozenset()
    assert (plant.world, plant.start_pose, plant.catalogue_parts, plant.describe()) == (None, None, (), None)
    assert plant.bus_devices() == () and plant.bus_notes("i2c0") == [] and plant.bus_device("i2c0", 0x68) is None
    assert plant.driven_inputs() == set() and plant.coverage_grid() is None and plant.footprint() == ()
    for capability, methods in CAPABILITIES.items():
        with pytest.raises(ContractError, match=f"ScriptedPlant has no '{capability}' capability"):
            method = getattr(plant, methods[0])
            method(*[None] * (len(inspect.signature(method).parameters)))


def test_the_fault_wrapper_answers_for_the_plant_inside_it():
    inner = assemble_file(APPS / "rover" / "rig.toml")
    plant = with_faults(inner, parse_faults(STUCK))
    assert plant is not inner and plant.unwrapped is inner and check_contract(plant) is plant
    assert plant.capabilities == inner.capabilities and POSE in plant.capabilities
    assert plant.world is inner.world and plant.start_pose == inner.start_pose
    assert plant.catalogue_parts == inner.catalogue_parts and plant.summary == inner.summary
    assert [f.kind for f in plant.fault_schedule] == ["stuck"] and inner.fault_schedule == ()
    assert plant.describe() == inner.describe() and plant.footprint() == inner.footprint() != ()
    assert plant.coverage_grid() is inner.coverage_grid() is not None
    assert plant.pose_at(0) == inner.pose_at(0)
    twice = with_faults(plant, parse_faults(STUCK))
    assert twice.unwrapped is inner, "a wrapper around a wrapper: the plant inside both"


def test_the_plant_base_is_the_one_interface():
    """Plant defines each capability's methods (raising), so a plant is asked nothing it lacks."""
    for methods in CAPABILITIES.values():
        for method in methods:
            assert callable(getattr(Plant, method)), method
