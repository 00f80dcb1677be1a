"""The .fmu archive itself: layout, exported symbols, bundled files."""

import json
import subprocess
import zipfile
from pathlib import Path

from conftest import REPO

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


def test_archive_layout(fmu_path):
    names = set(zipfile.ZipFile(fmu_path).namelist())
    assert {
        "modelDescription.xml",
        "binaries/linux64/Pacejka87Tire.so",
        "resources/pacejka87.json",
        "documentation/index.html",
    } <= names


def test_model_description_is_the_checked_in_one(fmu_path):
    packed = zipfile.ZipFile(fmu_path).read("modelDescription.xml")
    assert packed == (REPO / "modelDescription" / "modelDescription.xml").read_bytes()


def test_library_exports_exactly_the_fmi2_cosimulation_functions(unzipdir):
    so = Path(unzipdir) / "binaries" / "linux64" / "Pacejka87Tire.so"
    out = subprocess.run(
        ["nm", "-D", "--defined-only", str(so)], check=True, capture_output=True, text=True
    ).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.split()[1:2] == ["T"]}
    assert exported == FMI2_COSIMULATION_FUNCTIONS


def test_bundled_parameters_are_the_paper_table(fmu_path):
    params = json.loads(zipfile.ZipFile(fmu_path).read("resources/pacejka87.json"))
    assert params["Fy"]["a8"] == 0.707  # erratum 1
    assert (params["Fy"]["C"], params["Mz"]["C"], params["Fx"]["C"]) == (1.3, 2.4, 1.65)
    assert set(params["Fx"]) == {"C"} | {f"a{i}" for i in range(1, 9)}


def test_documentation_names_every_variable(fmu_path, model_description):
    html = zipfile.ZipFile(fmu_path).read("documentation/index.html").decode()
    for v in model_description.modelVariables:
        assert v.name in html
