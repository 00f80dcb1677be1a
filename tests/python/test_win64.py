"""The FMU's Windows binary, binaries/win64/Pacejka87Tire.dll, loaded and run under Wine by a
small C importer (tests/wine/fmu_harness.c, cross-compiled with mingw-w64 into target/wine),
and its import and export tables read with pefile.

The harness runs once: it loads the DLL from an unzipped FMU folder on the Wine prefix's C:
drive (`C:\\p87 harness`, a space in the name), gives the FMU its resources as a
`file:///C:/p87%20harness/resources` URI and prints `ok NAME` or `FAIL NAME: detail` per check.
Each check the harness must print is a test here, so a check that did not run fails too.

P87_WIN64_DLL=/path/to/Pacejka87Tire.dll tests that DLL instead of the one in target/fmu's FMU.
"""

import json
import os
import re
import shutil
import subprocess
import time
import xml.etree.ElementTree as ET
import zipfile
from typing import NamedTuple

import numpy as np
import pefile
import pytest

import magic_formula as mf
from conftest import FMI_FUNCTIONS, REPO

DLL_OVERRIDE = "P87_WIN64_DLL"
DLL_IN_FMU = "binaries/win64/Pacejka87Tire.dll"
WINE_DIR = REPO / "target" / "wine"
PREFIX = WINE_DIR / "prefix"  # shared with `cargo xtask`'s Wine runs
HARNESS_SOURCE = REPO / "tests" / "wine" / "fmu_harness.c"
MINGW_GCC = "x86_64-w64-mingw32-gcc"
SETUP_HINT = "scripts/setup.sh installs wine and mingw-w64 (gcc-mingw-w64-x86-64)"

FOLDER = "p87 harness"  # the unzipped FMU: C:\p87 harness
PARAMETER_FILE = "stiffer tire.json"  # in its resources folder, with Fy a2 changed
FY_A2 = 1263.75  # 1.25 times the paper's 1011, exact in binary
HARNESS_VARIABLES = ("Fz", "alpha", "kappa", "gamma", "Fx", "Fy", "Mz", "Fy_a2", "parameterFile")

EXPECTED_CHECKS = (
    "load_library", "resolve_functions", "version", "types_platform",
    "resource_uri", "parameter_file", "instantiate_and_initialize", "reference_values",
    "fmu_state_get_set", "fmu_state_serialize", "fmu_state_free",
    "null_instance", "step_before_initialization", "nan_input", "wrong_guid",
    "terminate", "free_instance", "free_library",
)


# DLLs in System32 of every Windows 10 (and Wine): the DLL may import these and nothing else.
SYSTEM_DLLS = {
    "kernel32.dll", "ntdll.dll", "advapi32.dll", "userenv.dll", "ws2_32.dll", "msvcrt.dll",
    "bcrypt.dll", "user32.dll", "shell32.dll", "ole32.dll", "oleaut32.dll", "secur32.dll",
}
# Why some that turn up in cross-built Rust DLLs are not acceptable.
NOT_SYSTEM = {
    "libgcc_s_seh-1.dll": "MinGW's runtime, not part of Windows (link it statically)",
    "libwinpthread-1.dll": "MinGW's runtime, not part of Windows (link it statically)",
    "libstdc++-6.dll": "MinGW's C++ runtime, not part of Windows",
    "bcryptprimitives.dll": "Rust's random source (ProcessPrng) on the Windows 10 target; Wine 8 "
    "lacks it; the win7 target avoids it",
}


def dll_names(entries):
    return sorted({e.dll.decode("ascii").lower() for e in entries})


@pytest.fixture(scope="module")
def win64(request):
    """(the DLL's bytes, the model description's text): from the FMU or from P87_WIN64_DLL."""
    override = os.environ.get(DLL_OVERRIDE)
    if override:
        if not os.path.isfile(override):
            pytest.fail(f"{DLL_OVERRIDE}={override}: no such file", pytrace=False)
        md = (REPO / "modelDescription" / "modelDescription.xml").read_text(encoding="utf-8")
        with open(override, "rb") as f:
            return f.read(), md
    fmu = request.getfixturevalue("fmu_path")
    with zipfile.ZipFile(fmu) as z:
        if DLL_IN_FMU not in z.namelist():
            pytest.fail(f"{fmu} has no {DLL_IN_FMU}: build the FMU with its Windows binary "
                        f"(`cargo xtask fmu` after scripts/setup.sh), or name a DLL with "
                        f"{DLL_OVERRIDE}=path", pytrace=False)
        return z.read(DLL_IN_FMU), z.read("modelDescription.xml").decode("utf-8")


@pytest.fixture(scope="module")
def pe(win64):
    return pefile.PE(data=win64[0])


def test_dll_is_a_64_bit_windows_dll(pe):
    assert pe.FILE_HEADER.Machine == pefile.MACHINE_TYPE["IMAGE_FILE_MACHINE_AMD64"]
    assert pe.is_dll()


def test_dll_imports_only_dlls_every_windows_10_has(pe):
    assert hasattr(pe, "DIRECTORY_ENTRY_IMPORT"), "no import table"
    delayed = getattr(pe, "DIRECTORY_ENTRY_DELAY_IMPORT", [])
    imported = dll_names(pe.DIRECTORY_ENTRY_IMPORT + delayed)
    foreign = [d for d in imported if d not in SYSTEM_DLLS]
    assert foreign == [], "imports that are not Windows system DLLs: " + "; ".join(
        f"{d}: {NOT_SYSTEM.get(d, 'not in the list of system DLLs')}" for d in foreign
    ) + f" (all imports: {imported})"


def test_dll_exports_exactly_the_fmi_functions(pe):
    assert hasattr(pe, "DIRECTORY_ENTRY_EXPORT"), "no export table"
    exported = [s.name.decode("ascii") if s.name else f"ordinal {s.ordinal}"
                for s in pe.DIRECTORY_ENTRY_EXPORT.symbols]
    assert len(exported) == len(set(exported)), exported
    missing, extra = FMI_FUNCTIONS - set(exported), set(exported) - FMI_FUNCTIONS
    assert (missing, extra) == (set(), set()), f"missing: {sorted(missing)}, extra: {sorted(extra)}"


# ---- the harness under Wine ----


def tool(name):
    path = shutil.which(name)
    if path is None:
        pytest.fail(f"`{name}` not found on PATH: {SETUP_HINT}", pytrace=False)
    return path


def fmi2_headers():
    """The FMI 2.0 standard headers bundled with the fmi-sys crate (a dependency of the FMU)."""
    p = subprocess.run(["cargo", "metadata", "--format-version", "1", "--locked"],
                       cwd=REPO, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, f"cargo metadata failed:\n{p.stderr}"
    fmi_sys = [k for k in json.loads(p.stdout)["packages"] if k["name"] == "fmi-sys"]
    assert len(fmi_sys) == 1, "fmi-sys is not (or more than once) in the dependency graph"
    headers = os.path.join(os.path.dirname(fmi_sys[0]["manifest_path"]), "fmi-standard2", "headers")
    assert os.path.isfile(os.path.join(headers, "fmi2FunctionTypes.h")), headers
    return headers


def wine_env():
    env = dict(os.environ, WINEPREFIX=str(PREFIX), WINEDEBUG="-all",
               WINEDLLOVERRIDES="mscoree,mshtml=")  # no Mono or Gecko install dialogs
    for display in ("DISPLAY", "WAYLAND_DISPLAY"):  # headless, on a desktop too
        env.pop(display, None)
    return env


def run_wine(name, args, timeout):
    """Runs `wine ARGS`; returns (exit status, stdout, stderr), also kept in target/wine/NAME.*.

    The output goes to files, not pipes: the wineserver that wine starts inherits the pipes
    and holds them open for seconds after the program has exited. Read back with universal
    newlines (the harness writes CRLF).
    """
    out, err = WINE_DIR / f"{name}.stdout", WINE_DIR / f"{name}.stderr"
    with open(out, "wb") as o, open(err, "wb") as e:
        try:
            status = subprocess.run([tool("wine"), *args], env=wine_env(), stdout=o, stderr=e,
                                    stdin=subprocess.DEVNULL, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            status = f"none, killed after {timeout} s"
    return (status,) + tuple(p.read_text(encoding="utf-8", errors="replace") for p in (out, err))


def write_fmu_folder(folder, dll, md_text, reference_rows):
    """The unzipped FMU on drive C:, the parameter file in its resources, and cases.txt with
    every reference row: the inputs in SI units and the expected Fx, Fy, Mz."""
    shutil.rmtree(folder, ignore_errors=True)
    (folder / "binaries" / "win64").mkdir(parents=True)
    (folder / "binaries" / "win64" / "Pacejka87Tire.dll").write_bytes(dll)
    (folder / "modelDescription.xml").write_text(md_text, encoding="utf-8")
    (folder / "resources").mkdir()
    params = mf.paper_table()
    params["Fy"]["a2"] = FY_A2
    (folder / "resources" / PARAMETER_FILE).write_text(json.dumps(params, indent=2))
    r = reference_rows
    cases = np.column_stack([r["fz_N"], np.radians(r["alpha_deg"]), r["kappa_pct"] / 100.0,
                             np.radians(r["gamma_deg"]), r["fx_N"], r["fy_N"], r["mz_Nm"]])
    lines = (" ".join(repr(float(v)) for v in row) + "\n" for row in cases)
    (folder / "cases.txt").write_text("".join(lines))


class HarnessRun(NamedTuple):
    status: object  # the exit status, or why there is none
    stdout: str
    stderr: str
    timings: str


@pytest.fixture(scope="module")
def harness(reference_rows, win64):
    """Builds the harness, prepares the prefix and the FMU folder and runs the harness once."""
    tool("wine")
    gcc = tool(MINGW_GCC)
    WINE_DIR.mkdir(parents=True, exist_ok=True)
    exe = WINE_DIR / "fmu_harness.exe"
    start = time.monotonic()
    cc = subprocess.run([gcc, "-std=c99", "-O2", "-Wall", "-Werror", "-municode",
                         "-I", fmi2_headers(), "-o", str(exe), str(HARNESS_SOURCE)],
                        capture_output=True, text=True, timeout=300)
    assert cc.returncode == 0, f"{MINGW_GCC} failed:\n{cc.stderr}"
    timings = [f"harness build {time.monotonic() - start:.1f} s"]

    if not (PREFIX / "drive_c").is_dir():  # the first start of Wine creates the prefix
        start = time.monotonic()
        _, _, stderr = run_wine("wineboot", ["wineboot.exe", "--init"], timeout=600)
        assert (PREFIX / "drive_c").is_dir(), f"no Wine prefix in {PREFIX}:\n{stderr}"
        timings.append(f"Wine prefix created {time.monotonic() - start:.1f} s")

    dll, md_text = win64
    md = ET.fromstring(md_text)
    vrs = {v.get("name"): v.get("valueReference") for v in md.iter("ScalarVariable")}
    write_fmu_folder(PREFIX / "drive_c" / FOLDER, dll, md_text, reference_rows)
    c = "C:\\" + FOLDER
    start = time.monotonic()
    status, stdout, stderr = run_wine("fmu_harness", [
        str(exe), c + r"\binaries\win64\Pacejka87Tire.dll", md.get("guid"),
        "file:///C:/" + FOLDER.replace(" ", "%20") + "/resources", c + r"\resources",
        PARAMETER_FILE, repr(FY_A2), c + r"\cases.txt",
        *(f"{name}={vrs[name]}" for name in HARNESS_VARIABLES),
    ], timeout=300)
    timings.append(f"harness run under Wine {time.monotonic() - start:.1f} s")
    print(", ".join(timings))
    return HarnessRun(status, stdout, stderr, ", ".join(timings))


def report(run):
    return (f"exit status {run.status} ({run.timings})\nstdout:\n{run.stdout}\n"
            f"stderr (end):\n{run.stderr[-3000:]}")


def test_harness_exits_with_status_0(harness):
    assert harness.status == 0 and not re.search("^FAIL", harness.stdout, re.M), report(harness)


@pytest.mark.parametrize("check", EXPECTED_CHECKS)
def test_harness_check_passes(harness, check):
    lines = [line for line in harness.stdout.splitlines()
             if re.match(rf"(ok|FAIL) {check}(:|$)", line)]
    assert lines == [f"ok {check}"], report(harness)


def test_harness_ran_exactly_the_expected_checks(harness):
    names = re.findall(r"^(?:ok|FAIL) (\w+)", harness.stdout, re.M)
    assert sorted(names) == sorted(EXPECTED_CHECKS), report(harness)


def test_harness_compared_every_reference_row(harness, reference_rows):
    assert f"reference cases compared: {len(reference_rows)}\n" in harness.stdout, report(harness)
