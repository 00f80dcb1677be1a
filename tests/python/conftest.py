"""Shared fixtures: where the repository, the built FMU and the reference CSV are."""

import shutil
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
FMU_PATH = REPO / "target" / "fmu" / "Pacejka87Tire.fmu"
# A copy of the team's shared reference values, kept in the repository.
REFERENCE_CSV = REPO / "tests" / "data" / "mf87_reference.csv"


@pytest.fixture(scope="session")
def fmu_path():
    """The built FMU; the test command builds it first (cargo xtask fmu)."""
    if not FMU_PATH.is_file():
        pytest.fail(
            f"FMU not found at {FMU_PATH}: build it first with `cargo xtask fmu`",
            pytrace=False,
        )
    return str(FMU_PATH)


@pytest.fixture(scope="session")
def unzipdir(fmu_path, tmp_path_factory):
    """The FMU extracted once for the FMU2Slave tests."""
    import fmpy

    target = tmp_path_factory.mktemp("fmu")
    fmpy.extract(fmu_path, unzipdir=str(target))
    yield str(target)
    shutil.rmtree(target, ignore_errors=True)


@pytest.fixture(scope="session")
def model_description(fmu_path):
    import fmpy

    return fmpy.read_model_description(fmu_path)


@pytest.fixture(scope="session")
def reference_rows():
    """mf87_reference.csv as a structured array (paper's units and sign convention)."""
    if not REFERENCE_CSV.is_file():
        pytest.fail(f"reference CSV not found at {REFERENCE_CSV}", pytrace=False)
    rows = np.genfromtxt(REFERENCE_CSV, delimiter=",", names=True, dtype=float)
    expected = ("fz_N", "alpha_deg", "gamma_deg", "kappa_pct", "fx_N", "fy_N", "mz_Nm")
    assert rows.dtype.names == expected, rows.dtype.names
    assert len(rows) > 400
    return rows
