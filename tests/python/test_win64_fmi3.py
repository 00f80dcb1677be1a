"""The FMI 3.0 archive's Windows binary, binaries/x86_64-windows/Pacejka87Tire.dll, loaded and
run under Wine by a small C importer (tests/wine/fmu3_harness.c, cross-compiled with mingw-w64
into target/wine): the FMI 3.0 counterpart of test_win64.py, whose Wine set-up it reuses.

The harness runs once: it loads the DLL from an unzipped FMU folder on the Wine prefix's C:
drive (`C:\\p87 fmi3 harness`, a space in the name), gives the FMU its resources as the plain
path `C:\\p87 fmi3 harness\\resources\\` and prints `ok NAME` or `FAIL NAME: detail` per check.
Each check the harness must print is a test here, so a check that did not run fails too.
"""

import re
import shutil
import subprocess
import time
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest

import test_win64 as w
from conftest import REPO

DLL_IN_FMU = "binaries/x86_64-windows/Pacejka87Tire.dll"
HARNESS_SOURCE = REPO / "tests" / "wine" / "fmu3_harness.c"
FOLDER = "p87 fmi3 harness"  # the unzipped FMU: C:\p87 fmi3 harness
HARNESS_VARIABLES = ("Fz", "alpha", "kappa", "gamma", "Fx", "Fy", "Mz", "Fy_coefficients",
                     "parameterFile")
# FMI 3.0 variable elements (the model description's children of ModelVariables).
VARIABLE_TAGS = ("Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32",
                 "Int64", "UInt64", "Boolean", "String", "Binary", "Enumeration", "Clock")

EXPECTED_CHECKS = (
    "load_library", "resolve_functions", "version",
    "resource_path", "parameter_file", "coefficient_array", "instantiate_and_initialize",
    "reference_values", "derivatives",
    "fmu_state_get_set", "fmu_state_serialize", "fmu_state_free",
    "null_instance", "step_before_initialization", "nan_input", "wrong_token",
    "terminate", "free_instance", "free_library",
)


@pytest.fixture(scope="module")
def win64_fmi3(fmu3_path):
    """(the DLL's bytes, the model description's text) from the FMI 3.0 FMU."""
    with zipfile.ZipFile(fmu3_path) as z:
        if DLL_IN_FMU not in z.namelist():
            pytest.fail(f"{fmu3_path} has no {DLL_IN_FMU}: build the FMU with its Windows "
                        f"binary (`cargo xtask fmu` after scripts/setup.sh)", pytrace=False)
        return z.read(DLL_IN_FMU), z.read("modelDescription.xml").decode("utf-8")


def fmi3_headers():
    """The FMI 3.0 standard headers bundled with the fmi-sys crate: fmi-standard3 beside
    the fmi-standard2 folder test_win64.fmi2_headers() finds."""
    headers = Path(w.fmi2_headers()).parent.parent / "fmi-standard3" / "headers"
    assert (headers / "fmi3FunctionTypes.h").is_file(), headers
    return str(headers)


def value_references(md):
    """{name: value reference} of the FMI 3.0 model description's variables."""
    variables = md.find("ModelVariables")
    assert variables is not None, "no ModelVariables"
    return {v.get("name"): v.get("valueReference") for v in variables
            if v.tag in VARIABLE_TAGS}


def write_fmu_folder(folder, dll, md_text, reference_rows):
    """test_win64's FMU folder (parameter file, cases.txt) with the DLL where FMI 3.0 puts
    it: binaries/x86_64-windows."""
    w.write_fmu_folder(folder, dll, md_text, reference_rows)
    shutil.rmtree(folder / "binaries")
    (folder / "binaries" / "x86_64-windows").mkdir(parents=True)
    (folder / "binaries" / "x86_64-windows" / "Pacejka87Tire.dll").write_bytes(dll)


@pytest.fixture(scope="module")
def harness(reference_rows, win64_fmi3):
    """Builds the harness, prepares the prefix and the FMU folder and runs the harness once."""
    w.tool("wine")
    gcc = w.tool(w.MINGW_GCC)
    w.WINE_DIR.mkdir(parents=True, exist_ok=True)
    exe = w.WINE_DIR / "fmu3_harness.exe"
    start = time.monotonic()
    cc = subprocess.run([gcc, "-std=c99", "-O2", "-Wall", "-Werror", "-municode",
                         "-I", fmi3_headers(), "-o", str(exe), str(HARNESS_SOURCE)],
                        capture_output=True, text=True, timeout=300)
    assert cc.returncode == 0, f"{w.MINGW_GCC} failed:\n{cc.stderr}"
    timings = [f"harness build {time.monotonic() - start:.1f} s"]

    if not (w.PREFIX / "drive_c").is_dir():  # the first start of Wine creates the prefix
        start = time.monotonic()
        _, _, stderr = w.run_wine("wineboot", ["wineboot.exe", "--init"], timeout=600)
        assert (w.PREFIX / "drive_c").is_dir(), f"no Wine prefix in {w.PREFIX}:\n{stderr}"
        timings.append(f"Wine prefix created {time.monotonic() - start:.1f} s")

    dll, md_text = win64_fmi3
    md = ET.fromstring(md_text)
    assert md.get("fmiVersion") == "3.0", md.get("fmiVersion")
    vrs = value_references(md)
    write_fmu_folder(w.PREFIX / "drive_c" / FOLDER, dll, md_text, reference_rows)
    c = "C:\\" + FOLDER
    start = time.monotonic()
    status, stdout, stderr = w.run_wine("fmu3_harness", [
        str(exe), c + r"\binaries\x86_64-windows\Pacejka87Tire.dll", md.get("instantiationToken"),
        c + "\\resources\\", w.PARAMETER_FILE, repr(w.FY_A2), c + r"\cases.txt",
        *(f"{name}={vrs[name]}" for name in HARNESS_VARIABLES),
    ], timeout=300)
    timings.append(f"harness run under Wine {time.monotonic() - start:.1f} s")
    print(", ".join(timings))
    return w.HarnessRun(status, stdout, stderr, ", ".join(timings))


def test_harness_exits_with_status_0(harness):
    assert harness.status == 0 and not re.search("^FAIL", harness.stdout, re.M), w.report(harness)


@pytest.mark.parametrize("check", EXPECTED_CHECKS)
def test_harness_check_passes(harness, check):
    lines = [line for line in harness.stdout.splitlines()
             if re.match(rf"(ok|FAIL) {check}(:|$)", line)]
    assert lines == [f"ok {check}"], w.report(harness)


def test_harness_ran_exactly_the_expected_checks(harness):
    names = re.findall(r"^(?:ok|FAIL) (\w+)", harness.stdout, re.M)
    assert sorted(names) == sorted(EXPECTED_CHECKS), w.report(harness)


def test_harness_compared_every_reference_row(harness, reference_rows):
    assert f"reference cases compared: {len(reference_rows)}\n" in harness.stdout, \
        w.report(harness)
