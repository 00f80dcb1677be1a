"""A second, independent co-simulation master: libcosim (Open Simulation Platform) through
libcosimpy. It unpacks and loads the FMU with its own FMI code, not fmpy's.

Inputs go in through an override manipulator (applied before the slave's fmi2DoStep), the
outputs come back through a last-value observer (read after it): each step's outputs
belong to the inputs overridden just before it.
"""

import numpy as np
import pytest

import magic_formula as mf

# A required test dependency (tests/python/requirements.txt): missing, the tests fail.
from libcosimpy.CosimEnums import CosimVariableCausality, CosimVariableType
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

STEP_NS = 10_000_000  # 0.01 s; libcosim counts time in nanoseconds

log_output_level(CosimLogLevel.WARNING)  # libcosim's own debug chatter off


@pytest.fixture
def execution(fmu_path):
    ex = CosimExecution.from_step_size(step_size=STEP_NS)
    slave = CosimLocalSlave(fmu_path=fmu_path, instance_name="tire")
    index = ex.add_local_slave(local_slave=slave)
    assert index >= 0, "libcosim could not load the FMU"
    manipulator = CosimManipulator.create_override()
    observer = CosimObserver.create_last_value()
    assert ex.add_manipulator(manipulator=manipulator)
    assert ex.add_observer(observer=observer)
    # Keep the Python wrappers alive as long as the execution uses them.
    yield ex, index, manipulator, observer, slave


def variables(ex, index):
    return {v.name.decode(): v for v in ex.slave_variables(slave_index=index)}


def test_libcosim_reads_the_interface(execution, model_description):
    ex, index, *_ = execution
    found = variables(ex, index)
    for v in model_description.modelVariables:
        assert v.name in found
        assert found[v.name].reference == v.valueReference
    for name in ("Fz", "alpha", "kappa", "gamma"):
        assert CosimVariableCausality(found[name].causality) == CosimVariableCausality.INPUT
        assert CosimVariableType(found[name].type) == CosimVariableType.REAL
    for name in ("Fx", "Fy", "Mz"):
        assert CosimVariableCausality(found[name].causality) == CosimVariableCausality.OUTPUT


def test_libcosim_slip_sweep_matches_the_formula(execution):
    ex, index, manipulator, observer, _ = execution
    vr = {name: v.reference for name, v in variables(ex, index).items()}
    # A start value for Fz, then the slip angle and later the load driven step by step.
    assert ex.real_initial_value(slave_index=index, variable_reference=vr["Fz"], value=6000.0)
    outputs = [vr["Fx"], vr["Fy"], vr["Mz"]]
    checked = 0
    for fz in (6000.0, 2500.0):
        if fz != 6000.0:
            assert manipulator.slave_real_values(index, [vr["Fz"]], [fz])
        for alpha_deg in (-10.0, -2.0, 0.5, 5.0, 12.0):
            assert manipulator.slave_real_values(index, [vr["alpha"]], [np.radians(alpha_deg)])
            assert ex.step(), "libcosim step failed"
            fx, fy, mz = observer.last_real_values(slave_index=index, variable_references=outputs)
            want = mf.tire_forces(fz, np.radians(alpha_deg), 0.0, 0.0)
            where = [f"Fz={fz} N alpha={alpha_deg} deg"]
            mf.assert_close("Fx", fx, want[0], context=where)
            mf.assert_close("Fy", fy, want[1], context=where)
            mf.assert_close("Mz", mz, want[2], context=where)
            checked += 1
    assert checked == 10
    assert ex.status().current_time == 10 * STEP_NS
