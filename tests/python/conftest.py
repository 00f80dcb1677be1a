"""Shared fixtures: where the repository, the built FMU and the reference CSV are."""

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
FMU_PATH = REPO / "target" / "fmu" / "Pacejka87Tire.fmu"
FMU3_PATH = REPO / "target" / "fmu" / "Pacejka87Tire-fmi3.fmu"
# Reference values computed independently of this code (docs/errata.md, "Reference values").
REFERENCE_CSV = REPO / "tests" / "data" / "mf87_reference.csv"

# FMI 2.0 for co-simulation: the common functions and the co-simulation ones; each binary
# exports exactly these.
FMI2_COSIMULATION_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal",
    "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger",
    "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate",
    "fmi2FreeFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate", "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives", "fmi2DoStep",
    "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus",
}
FMI2_MODEL_EXCHANGE_FUNCTIONS = {
    "fmi2EnterEventMode", "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep", "fmi2SetTime", "fmi2SetContinuousStates",
    "fmi2GetContinuousStates", "fmi2GetDerivatives", "fmi2GetNominalsOfContinuousStates",
    "fmi2GetEventIndicators",
}
# Both interfaces: the common, co-simulation and Model Exchange functions.
FMI2_FUNCTIONS = FMI2_COSIMULATION_FUNCTIONS | FMI2_MODEL_EXCHANGE_FUNCTIONS
# Every function of the FMI 3.0 header (fmi3Functions.h): the library exports them all
# (scheduled execution and clocks refuse with a logged error).
FMI3_FUNCTIONS = {
    "fmi3ActivateModelPartition", "fmi3CompletedIntegratorStep", "fmi3DeserializeFMUState",
    "fmi3DoStep", "fmi3EnterConfigurationMode", "fmi3EnterContinuousTimeMode",
    "fmi3EnterEventMode", "fmi3EnterInitializationMode", "fmi3EnterStepMode",
    "fmi3EvaluateDiscreteStates", "fmi3ExitConfigurationMode", "fmi3ExitInitializationMode",
    "fmi3FreeFMUState", "fmi3FreeInstance", "fmi3GetAdjointDerivative", "fmi3GetBinary",
    "fmi3GetBoolean", "fmi3GetClock", "fmi3GetContinuousStateDerivatives",
    "fmi3GetContinuousStates", "fmi3GetDirectionalDerivative", "fmi3GetEventIndicators",
    "fmi3GetFMUState", "fmi3GetFloat32", "fmi3GetFloat64", "fmi3GetInt16", "fmi3GetInt32",
    "fmi3GetInt64", "fmi3GetInt8", "fmi3GetIntervalDecimal", "fmi3GetIntervalFraction",
    "fmi3GetNominalsOfContinuousStates", "fmi3GetNumberOfContinuousStates",
    "fmi3GetNumberOfEventIndicators", "fmi3GetNumberOfVariableDependencies",
    "fmi3GetOutputDerivatives", "fmi3GetShiftDecimal", "fmi3GetShiftFraction",
    "fmi3GetString", "fmi3GetUInt16", "fmi3GetUInt32", "fmi3GetUInt64", "fmi3GetUInt8",
    "fmi3GetVariableDependencies", "fmi3GetVersion", "fmi3InstantiateCoSimulation",
    "fmi3InstantiateModelExchange", "fmi3InstantiateScheduledExecution", "fmi3Reset",
    "fmi3SerializeFMUState", "fmi3SerializedFMUStateSize", "fmi3SetBinary", "fmi3SetBoolean",
    "fmi3SetClock", "fmi3SetContinuousStates", "fmi3SetDebugLogging", "fmi3SetFMUState",
    "fmi3SetFloat32", "fmi3SetFloat64", "fmi3SetInt16", "fmi3SetInt32", "fmi3SetInt64",
    "fmi3SetInt8", "fmi3SetIntervalDecimal", "fmi3SetIntervalFraction", "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction", "fmi3SetString", "fmi3SetTime", "fmi3SetUInt16", "fmi3SetUInt32",
    "fmi3SetUInt64", "fmi3SetUInt8", "fmi3Terminate", "fmi3UpdateDiscreteStates",
}
# What the one library both archives hold exports.
FMI_FUNCTIONS = FMI2_FUNCTIONS | FMI3_FUNCTIONS


def third_party_tool(name):
    """Builds (or reuses) the tool third_party/<name> holds with its build.sh; returns the
    binary's path. The build is cached under target/third_party/<name>, keyed on the source
    tarball and build.sh, so only the first session after a change compiles it."""
    build = REPO / "third_party" / name / "build.sh"
    p = subprocess.run(["bash", str(build)], capture_output=True, text=True)
    lines = p.stdout.strip().splitlines()
    binary = Path(lines[-1]) if lines else None
    if p.returncode != 0 or binary is None or not binary.is_file():
        pytest.fail(f"{build} failed with status {p.returncode}:\n{p.stderr}", pytrace=False)
    return binary


def built(path):
    """The path of a built archive, or a failure saying how to build it."""
    if not path.is_file():
        pytest.fail(f"FMU not found at {path}: build it first with `cargo xtask fmu`", pytrace=False)
    return str(path)


def extracted(fmu, tmp_path_factory, name):
    """The archive `fmu` extracted once into a temporary folder (removed at the end)."""
    import fmpy

    target = tmp_path_factory.mktemp(name)
    fmpy.extract(fmu, unzipdir=str(target))
    yield str(target)
    shutil.rmtree(target, ignore_errors=True)


@pytest.fixture(scope="session")
def fmu_path():
    """The built FMU; the test command builds it first (cargo xtask fmu)."""
    return built(FMU_PATH)


@pytest.fixture(scope="session")
def fmu3_path():
    """The built FMI 3.0 FMU (cargo xtask fmu writes it beside the FMI 2.0 one)."""
    return built(FMU3_PATH)


@pytest.fixture(scope="session")
def unzipdir(fmu_path, tmp_path_factory):
    """The FMU extracted once for the FMU2Slave tests."""
    yield from extracted(fmu_path, tmp_path_factory, "fmu")


@pytest.fixture(scope="session")
def unzipdir3(fmu3_path, tmp_path_factory):
    """The FMI 3.0 FMU extracted once."""
    yield from extracted(fmu3_path, tmp_path_factory, "fmu3")


@pytest.fixture(scope="session")
def model_description(fmu_path):
    import fmpy

    return fmpy.read_model_description(fmu_path)


@pytest.fixture(scope="session")
def model_description3(fmu3_path):
    import fmpy

    return fmpy.read_model_description(fmu3_path)


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
