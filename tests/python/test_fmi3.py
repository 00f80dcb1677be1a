"""The FMI 3.0 FMU (Pacejka87Tire-fmi3.fmu) through fmpy: validation, the reference rows,
co-simulation and Model Exchange against the FMI 2.0 FMU, the coefficient arrays, exact
directional and adjoint derivatives against the independent formula (magic_formula.py),
FMU states, and hostile call sequences."""

import ctypes
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3LogMessageCallback
from fmpy.validation import validate_fmu

import magic_formula as mf
from fmu_helpers import INPUTS, OUTPUTS, applied_inputs, input_signals

ERROR = 3


class Log:
    """The FMI 3.0 log messages of the instances made in this module: (status, category,
    message). One callback object for the module's lifetime (ctypes must keep it alive)."""

    def __init__(self):
        self.records = []
        self.callback = fmi3LogMessageCallback(self._log)

    def _log(self, env, status, category, message):
        decode = lambda b: b.decode("utf-8", "replace") if b else ""
        self.records.append((status, decode(category), decode(message)))

    def since(self, n, min_status=0):
        return [r for r in self.records[n:] if r[0] >= min_status]


LOG = Log()


class Tire3:
    """One FMI 3.0 instance of the tire (co-simulation or Model Exchange), by variable names."""

    def __init__(self, unzipdir, md, interface="cs"):
        self.vars = {v.name: v for v in md.modelVariables}
        kind = FMU3Slave if interface == "cs" else FMU3Model
        attributes = md.coSimulation if interface == "cs" else md.modelExchange
        self.fmu = kind(
            guid=md.instantiationToken,
            unzipDirectory=unzipdir,
            modelIdentifier=attributes.modelIdentifier,
            instanceName=f"fmi3-{interface}",
        )
        self.fmu.instantiate(loggingOn=True, logMessage=LOG.callback)
        self.time = 0.0

    def vr(self, name):
        return self.vars[name].valueReference

    def set(self, **values):
        for name, value in values.items():
            v = self.vars[name]
            if v.type == "Boolean":
                self.fmu.setBoolean([v.valueReference], [bool(value)])
            elif v.type == "String":
                self.fmu.setString([v.valueReference], [str(value)])
            else:
                values = list(np.atleast_1d(value).astype(float))
                self.fmu.setFloat64([v.valueReference], values)

    def get(self, *names):
        return tuple(self.fmu.getFloat64([self.vr(n) for n in names]))

    def initialize(self, **parameters):
        self.set(**parameters)
        self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.exitInitializationMode()

    def step(self, h=0.01, **inputs):
        self.set(**inputs)
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=h)
        self.time += h
        return self.get(*OUTPUTS)

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


@pytest.fixture
def tire(unzipdir3, model_description3):
    t = Tire3(unzipdir3, model_description3)
    yield t
    t.fmu.freeInstance()


def status_of(call, *args, **kwargs):
    """The FMI status of an fmpy call: 0 when it returned, else the one it raised with."""
    try:
        call(*args, **kwargs)
        return 0
    except FMICallException as e:
        return e.status


def test_fmpy_validates_the_archive(fmu3_path, model_description3):
    assert validate_fmu(fmu3_path) == []
    md = model_description3
    assert md.fmiVersion == "3.0"
    assert md.coSimulation and md.modelExchange
    names = zipfile.ZipFile(fmu3_path).namelist()
    assert "binaries/x86_64-linux/Pacejka87Tire.so" in names
    assert not [n for n in names if n.startswith("binaries/linux64")]
    # The same variables as the FMI 2.0 FMU, the coefficients as arrays.
    arrays = {v.name: [int(d.start) for d in v.dimensions] for v in md.modelVariables if v.dimensions}
    assert arrays == {"Fy_coefficients": [14], "Mz_coefficients": [14], "Fx_coefficients": [9]}


def test_model_description_is_valid_against_the_fmi3_schema(unzipdir3):
    """The FMI 3.0 XSD (fmpy ships the standard's schema files) accepts the description, and
    it declares both derivative kinds (fmpy reads only FMI 2.0's attribute name)."""
    import os

    import fmpy
    from lxml import etree

    schema_dir = os.path.join(os.path.dirname(fmpy.__file__), "schema", "fmi3")
    schema = etree.XMLSchema(etree.parse(os.path.join(schema_dir, "fmi3ModelDescription.xsd")))
    doc = etree.parse(os.path.join(unzipdir3, "modelDescription.xml"))
    assert schema.validate(doc), schema.error_log
    for interface in ("CoSimulation", "ModelExchange"):
        element = doc.getroot().find(interface)
        assert element.get("providesDirectionalDerivatives") == "true"
        assert element.get("providesAdjointDerivatives") == "true"


def test_every_reference_row_to_1e_8(tire, reference_rows):
    r = reference_rows
    tire.initialize()
    got = []
    for row in r:
        got.append(tire.step(Fz=row["fz_N"], alpha=np.radians(row["alpha_deg"]),
                             kappa=row["kappa_pct"] / 100.0, gamma=np.radians(row["gamma_deg"])))
    got = np.array(got)
    mf.assert_close("Fx", got[:, 0], r["fx_N"])
    mf.assert_close("Fy", got[:, 1], r["fy_N"])
    mf.assert_close("Mz", got[:, 2], r["mz_Nm"])


def _signals():
    t = np.linspace(0.0, 2.0, 201)
    return input_signals(
        t,
        Fz=4000.0 + 1500.0 * np.sin(2.0 * t),
        alpha=0.15 * np.sin(3.0 * t),
        kappa=0.1 * np.sin(5.0 * t),
        gamma=0.03 * np.cos(t),
    )


@pytest.mark.parametrize("interface", ["CoSimulation", "ModelExchange"])
def test_simulates_as_the_fmi2_fmu_does(fmu_path, fmu3_path, interface):
    signals = _signals()
    options = dict(fmi_type=interface, stop_time=2.0, output_interval=0.01, input=signals,
                   output=list(OUTPUTS), start_values={"isoSignConvention": True})
    fmi2 = simulate_fmu(fmu_path, **options)
    fmi3 = simulate_fmu(fmu3_path, **options)
    assert len(fmi3) == len(fmi2) > 150
    for name in ("time",) + OUTPUTS:
        np.testing.assert_array_equal(fmi3[name], fmi2[name], err_msg=name)
    # And the outputs are the formula's at the inputs applied (in co-simulation, those of
    # the step before each row; in Model Exchange, those at the row's time).
    if interface == "CoSimulation":
        x = applied_inputs(fmi3, signals)
    else:
        x = {n: np.interp(fmi3["time"], signals["time"], signals[n]) for n in INPUTS}
    expected = np.array(mf.tire_forces(*[x[n] for n in INPUTS], iso=True))
    for k, name in enumerate(OUTPUTS):
        mf.assert_close(name, fmi3[name], expected[k])


def test_coefficient_arrays_set_and_read(tire):
    table = mf.paper_table()
    names = ["C"] + [f"a{i}" for i in range(1, 14)]
    # Readable from instantiation on: the paper's table.
    paper = [table["Fy"][n] for n in names]
    assert tire.fmu.getFloat64([tire.vr("Fy_coefficients")], 14) == paper
    modified = list(paper)
    modified[0] = 1.1  # C
    modified[3] = 900.0  # a3
    table["Fy"]["C"], table["Fy"]["a3"] = 1.1, 900.0
    tire.initialize(Fy_coefficients=modified)
    assert tire.fmu.getFloat64([tire.vr("Fy_coefficients")], 14) == modified
    fx, fy, mz = tire.step(Fz=3000.0, alpha=0.07, kappa=0.02, gamma=0.01)
    expected = mf.tire_forces(3000.0, 0.07, 0.02, 0.01, params=table)
    mf.assert_close("Fy", np.array([fy]), np.array([expected[1]]))
    mf.assert_close("Mz", np.array([mz]), np.array([expected[2]]))
    # nValues must count the elements.
    n = len(LOG.records)
    assert status_of(tire.fmu.getFloat64, [tire.vr("Fy_coefficients")], 13) == ERROR
    assert any("nValues = 13" in m and "hold 14 values" in m for _, _, m in LOG.since(n, ERROR))
    # A fixed parameter cannot change after initialization.
    assert status_of(tire.fmu.setFloat64, [tire.vr("Fx_coefficients")], [1.0] * 9) == ERROR


def test_directional_and_adjoint_derivatives_match_the_independent_formula(tire):
    """At 2000 random points: the Jacobian of (Fx, Fy, Mz) by (Fz, alpha, kappa, gamma) from
    directional derivatives (columns) equals the one from adjoint derivatives (rows), and both
    match central differences of the independent formula."""
    tire.initialize()
    rng = np.random.default_rng(11)
    unknown = [tire.vr(n) for n in OUTPUTS]
    known = [tire.vr(n) for n in INPUTS]
    steps = (1e-2, 1e-7, 1e-7, 1e-7)
    worst = 0.0
    for _ in range(2000):
        x = [rng.uniform(300.0, 7500.0), rng.uniform(-1.4, 1.4), rng.uniform(-0.9, 0.9),
             rng.uniform(-0.08, 0.08)]
        tire.set(**dict(zip(INPUTS, x)))
        columns = np.array([tire.fmu.getDirectionalDerivative(unknown, known, list(np.eye(4)[k]))
                            for k in range(4)]).T
        rows = np.array([tire.fmu.getAdjointDerivative(unknown, known, list(np.eye(3)[i]), nSensitivity=4)
                         for i in range(3)])
        np.testing.assert_array_equal(rows, columns)
        for k, h in enumerate(steps):
            up, down = list(x), list(x)
            up[k] += h
            down[k] -= h
            fd = (np.array(mf.tire_forces(*up)) - np.array(mf.tire_forces(*down))) / (2 * h)
            err = np.abs(columns[:, k] - fd) / np.maximum(np.abs(fd), 10.0)
            worst = max(worst, err.max())
            assert err.max() < 1e-5, f"d{OUTPUTS}/d{INPUTS[k]} at {x}: {columns[:, k]} vs {fd}"
    print(f"worst relative difference from central differences: {worst:.2e}")


def test_adjoint_and_directional_agree_at_thousands_of_points(tire):
    """vᵀ (J u) = (vᵀ J) u for random seeds at random inputs."""
    tire.initialize()
    rng = np.random.default_rng(5)
    unknown = [tire.vr(n) for n in OUTPUTS]
    known = [tire.vr(n) for n in INPUTS]
    worst = 0.0
    for _ in range(2000):
        x = [rng.uniform(300.0, 9500.0), rng.uniform(-1.5, 1.5), rng.uniform(-0.95, 0.95),
             rng.uniform(-0.17, 0.17)]
        tire.set(**dict(zip(INPUTS, x)))
        u = rng.normal(size=4) * np.array([1e3, 0.1, 0.1, 0.05])
        v = rng.normal(size=3)
        ju = np.array(tire.fmu.getDirectionalDerivative(unknown, known, list(u)))
        vj = np.array(tire.fmu.getAdjointDerivative(unknown, known, list(v), nSensitivity=4))
        lhs, rhs = v @ ju, vj @ u
        scale = np.abs(v) @ np.abs(ju) + 1e-9
        worst = max(worst, abs(lhs - rhs) / scale)
    assert worst < 1e-13


def test_model_exchange_state_derivatives_and_adjoint(unzipdir3, model_description3):
    t = Tire3(unzipdir3, model_description3, interface="me")
    try:
        t.fmu.enterInitializationMode(startTime=0.0)
        t.fmu.exitInitializationMode()
        t.fmu.updateDiscreteStates()
        t.fmu.enterContinuousTimeMode()
        assert t.fmu.getNumberOfContinuousStates() == 3
        t.fmu.setTime(0.5)
        t.set(alpha=0.1, kappa=0.05, Fz=5000.0)
        outputs = t.get(*OUTPUTS)
        expected = mf.tire_forces(5000.0, 0.1, 0.05, 0.0)
        mf.assert_close("Fy", np.array(outputs[1:2]), np.array(expected[1:2]))
        # Knowns: inputs and states; unknowns: outputs and state derivatives.
        unknown = [t.vr(n) for n in OUTPUTS + ("der(lag_Fx)", "der(lag_Fy)", "der(lag_Mz)")]
        known = [t.vr(n) for n in INPUTS + ("lag_Fx", "lag_Fy", "lag_Mz")]
        rng = np.random.default_rng(3)
        for _ in range(50):
            u, v = rng.normal(size=len(known)), rng.normal(size=len(unknown))
            ju = np.array(t.fmu.getDirectionalDerivative(unknown, known, list(u)))
            vj = np.array(t.fmu.getAdjointDerivative(unknown, known, list(v), nSensitivity=len(known)))
            assert v @ ju == pytest.approx(vj @ u, rel=1e-12, abs=1e-9)
        t.fmu.enterEventMode()
        t.fmu.terminate()
    finally:
        t.fmu.freeInstance()


def test_fmu_state_round_trip(tire):
    tire.initialize()
    before = tire.step(Fz=4200.0, alpha=0.05, kappa=0.01)
    state = tire.fmu.getFMUState()
    after = tire.step(Fz=2000.0, alpha=-0.2, kappa=-0.3)
    assert after != before
    tire.fmu.setFMUState(state)
    assert tire.get(*OUTPUTS) == before
    # The time came back with the state: the next step starts where the state was taken.
    assert tire.fmu.getFloat64([tire.vr("time")]) == [0.01]
    tire.time = 0.01
    blob = tire.fmu.serializeFMUState(state)
    tire.step(Fz=2500.0, alpha=0.3, kappa=0.2)
    restored = tire.fmu.deserializeFMUState(blob)
    tire.fmu.setFMUState(restored)
    assert tire.get(*OUTPUTS) == before
    tire.fmu.freeFMUState(restored)
    tire.fmu.freeFMUState(state)
    tire.time = 0.01
    assert tire.step(Fz=2000.0, alpha=-0.2, kappa=-0.3) == after


def test_hostile_call_sequences_are_errors_not_crashes(unzipdir3, model_description3):
    t = Tire3(unzipdir3, model_description3)
    n = len(LOG.records)
    f = t.fmu
    # Before initialization: no step, no outputs (calculated), no derivatives; inputs and
    # parameters read back.
    assert status_of(f.doStep, 0.0, 0.01) == ERROR
    assert status_of(f.getFloat64, [t.vr("Fy")]) == ERROR
    assert f.getFloat64([t.vr("Fz")]) == [4000.0]
    assert status_of(f.getDirectionalDerivative, [t.vr("Fy")], [t.vr("alpha")], [1.0]) == ERROR
    # Model Exchange functions on a co-simulation instance.
    assert status_of(f.fmi3EnterContinuousTimeMode, f.component) == ERROR
    f.enterInitializationMode(startTime=0.0)
    f.exitInitializationMode()
    # Wrong types, unknown references, the independent variable.
    assert status_of(f.getFloat64, [t.vr("isoSignConvention")]) == ERROR
    assert status_of(f.getFloat64, [999]) == ERROR
    assert status_of(f.setFloat64, [t.vr("time")], [3.0]) == ERROR
    assert status_of(f.getInt32, [t.vr("Fy")]) == ERROR
    assert f.getFloat64([t.vr("time")]) == [0.0]
    # Outputs cannot be set; a step must start at the FMU's time.
    assert status_of(f.setFloat64, [t.vr("Fy")], [1.0]) == ERROR
    assert status_of(f.doStep, 5.0, 0.01) == ERROR
    # An FMI 2.0 function given this FMI 3.0 instance is refused.
    lib = ctypes.CDLL(f"{unzipdir3}/binaries/x86_64-linux/Pacejka87Tire.so")
    vr, value = (ctypes.c_uint * 1)(t.vr("Fy")), (ctypes.c_double * 1)()
    assert lib.fmi2GetReal(ctypes.c_void_p(f.component), vr, ctypes.c_size_t(1), value) == ERROR
    # NULL instance.
    assert lib.fmi3Terminate(None) == ERROR
    messages = [m for _, _, m in LOG.since(n, ERROR)]
    assert any("fmi3DoStep: Illegal call sequence: not allowed in state Instantiated" in m for m in messages)
    assert any("fmi3GetFloat64: Fy is calculated" in m for m in messages)
    assert any("fmi3EnterContinuousTimeMode: not a function of co-simulation" in m for m in messages)
    assert any("it takes only fmi2 functions" in m or "it takes only fmi3 functions" in m for m in messages)
    # Still usable after all that; terminate and free in any state.
    t.step(alpha=0.05)
    f.terminate()
    assert status_of(f.doStep, t.time, 0.01) == ERROR
    f.reset()
    f.enterInitializationMode(startTime=0.0)
    f.freeInstance()


def test_instantiation_refuses_bad_arguments(unzipdir3, model_description3):
    md = model_description3
    lib = ctypes.CDLL(f"{unzipdir3}/binaries/x86_64-linux/Pacejka87Tire.so")
    lib.fmi3InstantiateCoSimulation.restype = ctypes.c_void_p
    lib.fmi3InstantiateScheduledExecution.restype = ctypes.c_void_p
    n = len(LOG.records)
    args = lambda token, event_mode: (
        b"x", token, b"", False, True, event_mode, False, None, ctypes.c_size_t(0), None,
        LOG.callback, None,
    )
    assert lib.fmi3InstantiateCoSimulation(*args(b"{wrong}", False)) is None
    assert lib.fmi3InstantiateCoSimulation(*args(md.instantiationToken.encode(), True)) is None
    assert lib.fmi3InstantiateScheduledExecution(
        b"x", md.instantiationToken.encode(), b"", False, True, None, LOG.callback, None, None, None
    ) is None
    messages = [m for _, _, m in LOG.since(n, ERROR)]
    assert any("instantiationToken {wrong} does not match" in m for m in messages), messages
    assert any("eventModeUsed = true" in m for m in messages), messages
    assert any("not scheduled execution" in m for m in messages), messages
    ok = lib.fmi3InstantiateCoSimulation(*args(md.instantiationToken.encode(), False))
    assert ok
    lib.fmi3FreeInstance(ctypes.c_void_p(ok))
