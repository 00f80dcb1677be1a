"""The FMU driven call by call through fmpy.fmi2.FMU2Slave: instances, reset, FMU state,
sign convention and parameter files.

Each step sets inputs and then calls fmi2DoStep: the outputs read after it belong to them.
"""

import itertools
import json
import math
import os

import pytest
from fmpy.fmi1 import FMICallException

import magic_formula as mf
from fmu_helpers import Tire, deg

_names = (f"tire{i}" for i in itertools.count())


@pytest.fixture
def make_tire(unzipdir, model_description):
    """Factory of fresh instances (unique names), freed after the test."""
    made = []

    def make(logging_on=True):
        tire = Tire(unzipdir, model_description, next(_names), logging_on)
        made.append(tire)
        return tire

    yield make
    for tire in made:
        tire.free()


def expect(outputs, fz, alpha, kappa, gamma, **kw):
    """Assert FMU outputs (Fx, Fy, Mz) equal the formula's at these SI inputs."""
    for name, got, want in zip(("Fx", "Fy", "Mz"), outputs, mf.tire_forces(fz, alpha, kappa, gamma, **kw)):
        mf.assert_close(name, got, want, context=[f"Fz={fz} alpha={alpha} kappa={kappa} gamma={gamma} {kw}"])


A = dict(Fz=3000.0, alpha=deg(3.0), kappa=0.04, gamma=deg(1.5))
B = dict(Fz=7000.0, alpha=deg(-6.0), kappa=-0.15, gamma=deg(-3.0))


def args(x):
    return x["Fz"], x["alpha"], x["kappa"], x["gamma"]


def test_initialization_computes_outputs(make_tire):
    tire = make_tire()
    tire.fmu.setupExperiment(startTime=0.0)
    tire.fmu.enterInitializationMode()
    tire.set(**A)
    tire.fmu.exitInitializationMode()
    expect(tire.outputs(), *args(A))


def test_two_instances_are_independent(make_tire):
    a, b = make_tire(), make_tire()
    a.initialize()
    b.initialize(isoSignConvention=True)
    for _ in range(3):  # interleaved, each with its own inputs and convention
        out_a = a.step(**A)
        out_b = b.step(**B)
        expect(out_a, *args(A))
        expect(out_b, *args(B), iso=True)
    assert a.inputs() == args(A) and b.inputs() == args(B)
    # Changing one leaves the other as it was.
    b.step(alpha=deg(9.0))
    assert a.outputs() == out_a
    expect(a.step(), *args(A))


def test_instances_on_two_threads(make_tire):
    """ctypes releases the GIL during FMI calls, so the instances really run concurrently."""
    from concurrent.futures import ThreadPoolExecutor

    def run(tire, x, iso):
        tire.initialize(isoSignConvention=iso)
        alphas = [x["alpha"] * (1 + k / 100) for k in range(300)]
        return alphas, [tire.step(**{**x, "alpha": a}) for a in alphas]

    jobs = [(make_tire(logging_on=False), A, False), (make_tire(logging_on=False), B, True)]
    with ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda j: run(*j), jobs))
    for (_, x, iso), (alphas, outs) in zip(jobs, results):
        for a, out in zip(alphas, outs):
            expect(out, x["Fz"], a, x["kappa"], x["gamma"], iso=iso)


def test_reset_returns_to_start_values(make_tire, model_description):
    tire = make_tire()
    tire.initialize(start_time=0.0, Fy_a2=900.0, isoSignConvention=True)
    for _ in range(3):
        tire.step(0.1, **B)
    assert tire.last_successful_time() == pytest.approx(0.3)
    tire.fmu.reset()
    # Instantiated again: the same calls as after fmi2Instantiate are accepted.
    tire.initialize(start_time=0.0)
    starts = {v.name: float(v.start) for v in model_description.modelVariables if v.causality == "input"}
    assert tire.inputs() == tuple(starts[n] for n in ("Fz", "alpha", "kappa", "gamma"))
    assert tire.last_successful_time() == 0.0
    # Time starts again at 0, and Fz, kappa, gamma, Fy_a2 and the convention are the defaults.
    out = tire.step(0.1, alpha=deg(4.0))
    assert tire.last_successful_time() == pytest.approx(0.1)
    expect(out, starts["Fz"], deg(4.0), starts["kappa"], starts["gamma"])


def test_get_and_set_fmu_state(make_tire):
    tire = make_tire()
    tire.initialize()
    saved_out = tire.step(**A)
    saved_time = tire.time
    state = tire.fmu.getFMUstate()
    changed = tire.step(**B)
    assert changed != saved_out
    tire.fmu.setFMUstate(state)
    assert tire.outputs() == saved_out
    assert tire.inputs() == args(A)
    assert tire.last_successful_time() == pytest.approx(saved_time)
    tire.time = saved_time  # the communication point is the restored one
    assert tire.step() == saved_out
    tire.fmu.freeFMUstate(state)


def test_serialized_state_restores_a_fresh_instance(make_tire):
    source = make_tire()
    source.initialize(isoSignConvention=True)  # parameters are part of the state too
    saved_out = source.step(**A)
    saved_time = source.time
    state = source.fmu.getFMUstate()
    blob = source.fmu.serializeFMUstate(state)
    source.fmu.freeFMUstate(state)
    assert isinstance(blob, bytes) and len(blob) > 0
    source.step(**B)  # the blob does not follow the source's later changes

    fresh = make_tire()
    fresh.initialize()
    fresh.step(**B)
    restored = fresh.fmu.deSerializeFMUstate(blob)
    fresh.fmu.setFMUstate(restored)
    fresh.fmu.freeFMUstate(restored)
    # Bit for bit: a state that went through bytes must be the state that was saved.
    assert fresh.outputs() == saved_out
    assert fresh.inputs() == args(A)
    assert fresh.last_successful_time() == pytest.approx(saved_time)
    fresh.time = saved_time
    expect(fresh.step(), *args(A), iso=True)


def test_iso_sign_convention_flips_fy_and_mz_only(make_tire):
    paper, iso = make_tire(), make_tire()
    paper.initialize()
    iso.initialize(isoSignConvention=True)
    for x in (A, B, dict(Fz=4000.0, alpha=0.0, kappa=0.1, gamma=deg(4.0))):
        p, i = paper.step(**x), iso.step(**x)
        assert i == (p[0], -p[1], -p[2])  # not Fy(-alpha, gamma): camber keeps its sign
        expect(i, *args(x), iso=True)
        expect(p, *args(x))
    # ISO 8855: alpha > 0 gives Fy < 0 and Mz > 0.
    fx, fy, mz = iso.step(Fz=4000.0, alpha=deg(4.0), kappa=0.0, gamma=0.0)
    assert fy < -1000.0 and mz > 0.0


def test_coefficient_parameter_changes_the_outputs(make_tire):
    params = mf.paper_table()
    params["Mz"]["a8"] = -3.5
    tire = make_tire()
    tire.initialize(Mz_a8=-3.5)
    expect(tire.step(**A), *args(A), params=params)


def write_params(path, params):
    path.write_text(json.dumps(params, indent=2))
    return path


@pytest.mark.parametrize("as_uri", [False, True], ids=["path", "file-uri"])
def test_parameter_file_changes_outputs(make_tire, tmp_path, as_uri):
    params = mf.paper_table()
    params["Fy"]["a2"] *= 1.25
    path = write_params(tmp_path / "stiffer tire.json", params)  # a space: URIs need %20
    tire, default = make_tire(), make_tire()
    tire.initialize(parameterFile=path.as_uri() if as_uri else str(path))
    default.initialize()
    for x in (A, B):
        out, base = tire.step(**x), default.step(**x)
        expect(out, *args(x), params=params)
        assert out[0] == base[0] and out[2] == base[2]  # Fx and Mz do not use Fy's a2
        assert abs(out[1] - base[1]) > 50.0
    # logEvents promises a message on loading a parameter file.
    assert any(n in m for _, _, m in tire.messages() for n in ("stiffer tire.json", "stiffer%20tire.json"))


def test_parameter_file_by_resource_name(make_tire, unzipdir):
    """A bare name is looked up in the FMU's resources folder (the FMU ships the table)."""
    assert os.path.isfile(os.path.join(unzipdir, "resources", "pacejka87.json"))
    tire = make_tire()
    tire.initialize(parameterFile="pacejka87.json")
    expect(tire.step(**B), *args(B))
    assert any("pacejka87.json" in m for _, _, m in tire.messages())


def test_missing_parameter_file_fails_initialization(make_tire, tmp_path):
    tire = make_tire()
    tire.fmu.setupExperiment(startTime=0.0)
    tire.set(parameterFile=str(tmp_path / "nowhere.json"))
    with pytest.raises(FMICallException):
        tire.fmu.enterInitializationMode()
    assert any("nowhere.json" in m for _, _, m in tire.messages(min_status=3))


def test_invalid_parameter_file_fails_initialization(make_tire, tmp_path):
    params = mf.paper_table()
    params["Mz"]["a13"] = 0.2  # 1 - a13 |gamma| < 0 at |gamma| = 10 deg
    path = write_params(tmp_path / "bad.json", params)
    tire = make_tire(logging_on=False)  # errors are logged regardless
    tire.fmu.setupExperiment(startTime=0.0)
    tire.set(parameterFile=str(path))
    with pytest.raises(FMICallException) as failed:
        tire.fmu.enterInitializationMode()
    assert failed.value.status >= 3  # fmi2Error or fmi2Fatal
    errors = [m for s, _, m in tire.messages(min_status=3)]
    assert any("a13" in m and "Mz" in m for m in errors), errors


def test_incomplete_parameter_file_is_rejected(make_tire, tmp_path):
    params = mf.paper_table()
    del params["Fx"]["a8"]
    path = write_params(tmp_path / "incomplete.json", params)
    tire = make_tire()
    tire.fmu.setupExperiment(startTime=0.0)
    tire.set(parameterFile=str(path))
    with pytest.raises(FMICallException):
        tire.fmu.enterInitializationMode()
    errors = [m for s, _, m in tire.messages(min_status=3)]
    assert any("a8" in m for m in errors), errors


def test_load_and_camber_are_clamped_to_the_limits(make_tire):
    tire = make_tire()
    tire.initialize()
    clamped = tire.step(Fz=25e3, alpha=deg(3.0), kappa=0.1, gamma=deg(15.0))
    at_limit = tire.step(Fz=10e3, alpha=deg(3.0), kappa=0.1, gamma=deg(10.0))
    assert clamped == at_limit
    expect(at_limit, 10e3, deg(3.0), 0.1, deg(10.0))


def test_lifted_wheel_gives_no_force(make_tire):
    tire = make_tire()
    tire.initialize()
    for fz in (0.0, -500.0):
        assert tire.step(Fz=fz, alpha=deg(5.0), kappa=0.1, gamma=deg(2.0)) == (0.0, 0.0, 0.0)
    out = tire.step(Fz=1.0, alpha=deg(5.0), kappa=0.1, gamma=deg(2.0))
    assert all(math.isfinite(v) and abs(v) < 20.0 for v in out)
    expect(out, 1.0, deg(5.0), 0.1, deg(2.0))
