"""What the FMU tells its logger about rejected and clamped values.

The logger is a Python callback handed to fmi2Instantiate through fmpy's callbacks struct
(see fmu_helpers.LogCapture); loggingOn=True enables the warning category, errors are
logged whatever loggingOn says.
"""

import itertools
import math

import pytest

import magic_formula as mf
from fmu_helpers import Tire, deg

OK, WARNING, ERROR = 0, 1, 3
_names = (f"logged{i}" for i in itertools.count())


@pytest.fixture
def tire(unzipdir, model_description):
    t = Tire(unzipdir, model_description, next(_names), logging_on=True)
    t.initialize()
    yield t
    t.free()


def naming(messages, *words):
    """Messages that contain every word (case-insensitive)."""
    return [m for _, _, m in messages if all(w.lower() in m.lower() for w in words)]


def test_nan_input_is_rejected_and_the_old_value_kept(tire):
    before = tire.step(Fz=4000.0, alpha=deg(4.0), kappa=0.05, gamma=deg(1.0))
    assert tire.set_real_status(tire.vr("alpha"), math.nan) == ERROR
    assert naming(tire.messages(min_status=ERROR), "alpha", "nan"), tire.messages()
    assert tire.get("alpha") == (deg(4.0),)
    after = tire.step()
    assert all(math.isfinite(v) for v in after)
    assert after == before


@pytest.mark.parametrize("value", [math.inf, -math.inf])
def test_infinite_input_is_rejected(tire, value):
    tire.step(Fz=4000.0, kappa=0.02)
    assert tire.set_real_status(tire.vr("kappa"), value) == ERROR
    assert naming(tire.messages(min_status=ERROR), "kappa", "inf")
    assert tire.get("kappa") == (0.02,)


def test_slip_angle_beyond_90_deg_is_clamped_with_a_warning(tire):
    at_limit = tire.step(Fz=4000.0, alpha=math.pi / 2, kappa=0.0, gamma=0.0)
    assert tire.messages(min_status=WARNING) == []
    status = tire.set_real_status(tire.vr("alpha"), 2.0)
    assert status in (OK, WARNING)  # the warning may come with fmi2SetReal or fmi2DoStep
    beyond = tire.step()
    assert naming(tire.messages(min_status=WARNING), "alpha"), tire.messages()
    assert all(s == WARNING for s, _, _ in tire.messages(min_status=WARNING))
    assert beyond == at_limit
    for name, got, want in zip(("Fx", "Fy", "Mz"), beyond, mf.tire_forces(4000.0, math.pi / 2, 0.0, 0.0)):
        mf.assert_close(name, got, want)


def test_fixed_parameter_cannot_change_after_initialization(tire):
    before = tire.step(Fz=4000.0, alpha=deg(4.0))
    assert tire.set_real_status(tire.vr("Fy_a1"), -30.0) == ERROR
    assert naming(tire.messages(min_status=ERROR), "Fy_a1"), tire.messages()
    assert tire.get("Fy_a1") == (-22.1,)
    assert tire.outputs() == before


def test_unknown_value_reference_is_an_error(tire):
    assert tire.get_real_status(9999) == ERROR
    assert naming(tire.messages(min_status=ERROR), "9999"), tire.messages()
    logged = len(tire.messages())
    assert tire.set_real_status(9999, 1.0) == ERROR
    new_errors = [r for r in tire.messages()[logged:] if r[0] >= ERROR]
    assert naming(new_errors, "9999"), tire.messages()


def test_errors_are_logged_without_logging_on(unzipdir, model_description):
    quiet = Tire(unzipdir, model_description, next(_names), logging_on=False)
    try:
        quiet.initialize()
        quiet.step(Fz=4000.0, alpha=2.0)  # clamped: a warning, not logged when off
        assert quiet.messages(min_status=WARNING) == []
        assert quiet.set_real_status(quiet.vr("alpha"), math.nan) == ERROR
        assert naming(quiet.messages(min_status=ERROR), "alpha", "nan")
    finally:
        quiet.free()
