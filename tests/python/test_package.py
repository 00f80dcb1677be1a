"""The .fmu archive itself: layout, exported symbols, bundled files."""

import json
import re
import subprocess
import zipfile
from pathlib import Path

from elftools.elf.dynamic import DynamicSection
from elftools.elf.elffile import ELFFile
from elftools.elf.gnuversions import GNUVerNeedSection

from conftest import FMI_FUNCTIONS, REPO


def test_archive_layout(fmu_path):
    names = set(zipfile.ZipFile(fmu_path).namelist())
    assert {
        "modelDescription.xml",
        "binaries/linux64/Pacejka87Tire.so",
        "binaries/win64/Pacejka87Tire.dll",
        "resources/pacejka87.json",
        "documentation/index.html",
    } <= names


def test_model_description_is_the_checked_in_one(fmu_path, fmu3_path):
    packed = zipfile.ZipFile(fmu_path).read("modelDescription.xml")
    assert packed == (REPO / "modelDescription" / "modelDescription.xml").read_bytes()
    packed = zipfile.ZipFile(fmu3_path).read("modelDescription.xml")
    assert packed == (REPO / "modelDescription" / "fmi3" / "modelDescription.xml").read_bytes()


def test_fmi3_archive_holds_the_same_binaries_under_platform_tuples(fmu_path, fmu3_path):
    fmi2, fmi3 = zipfile.ZipFile(fmu_path), zipfile.ZipFile(fmu3_path)
    assert set(fmi3.namelist()) == {
        "modelDescription.xml",
        "binaries/x86_64-linux/Pacejka87Tire.so",
        "binaries/x86_64-windows/Pacejka87Tire.dll",
        "resources/pacejka87.json",
        "documentation/index.html",
    }
    for old, new in (("linux64", "x86_64-linux"), ("win64", "x86_64-windows")):
        ext = "so" if old == "linux64" else "dll"
        name = f"Pacejka87Tire.{ext}"
        assert fmi3.read(f"binaries/{new}/{name}") == fmi2.read(f"binaries/{old}/{name}")
    assert fmi3.read("resources/pacejka87.json") == fmi2.read("resources/pacejka87.json")


# What every Linux has: a binary needing more does not load everywhere.
LINUX_LIBRARIES = {"libc.so.6", "libm.so.6", "libdl.so.2", "libpthread.so.0", "ld-linux-x86-64.so.2"}
OLDEST_GLIBC = (2, 17)


def elf_dependencies(path):
    """(exported names, needed libraries, {library: [symbol versions needed]}) of a shared
    library, read from its dynamic section, dynamic symbols and version-needs section."""
    with open(path, "rb") as f:
        elf = ELFFile(f)
        symbols = elf.get_section_by_name(".dynsym")
        exported = {
            s.name
            for s in symbols.iter_symbols()
            if s["st_shndx"] != "SHN_UNDEF" and s["st_info"]["bind"] in ("STB_GLOBAL", "STB_WEAK")
        }
        needed = set()
        for section in elf.iter_sections():
            if isinstance(section, DynamicSection):
                needed |= {t.needed for t in section.iter_tags() if t.entry.d_tag == "DT_NEEDED"}
        versions = {}
        for section in elf.iter_sections():
            if isinstance(section, GNUVerNeedSection):
                for need, aux in section.iter_versions():
                    versions[need.name] = sorted(a.name for a in aux)
    return exported, needed, versions


def linux_problems(path):
    """Everything that keeps a shared library from loading on any Linux with glibc >= 2.17
    or that it exports beyond the FMI functions."""
    exported, needed, versions = elf_dependencies(path)
    problems = [f"exports {n}" for n in sorted(exported - FMI_FUNCTIONS)]
    problems += [f"does not export {n}" for n in sorted(FMI_FUNCTIONS - exported)]
    problems += [f"needs {lib}" for lib in sorted(needed - LINUX_LIBRARIES)]
    for lib, names in versions.items():
        for name in names:
            m = re.fullmatch(r"GLIBC_(\d+)\.(\d+)(?:\.\d+)?", name)
            if m is None or (int(m[1]), int(m[2])) > OLDEST_GLIBC:
                problems.append(f"needs {name} from {lib}")
    return problems


def test_linux_library_loads_on_glibc_2_17_and_exports_only_fmi(unzipdir):
    so = Path(unzipdir) / "binaries" / "linux64" / "Pacejka87Tire.so"
    assert linux_problems(so) == []
    exported, needed, versions = elf_dependencies(so)
    assert exported == FMI_FUNCTIONS
    assert "libc.so.6" in needed and "libc.so.6" in versions


def test_the_linux_check_finds_what_it_looks_for():
    # libstdc++ (gcc's, on every machine that builds the project) needs glibc symbols newer
    # than 2.17, exports C++ names and needs libraries beyond the base set. gcc names the
    # file it links with.
    found = subprocess.run(
        ["gcc", "-print-file-name=libstdc++.so.6"], capture_output=True, text=True, check=True
    ).stdout.strip()
    libstdcxx = Path(found)
    assert libstdcxx.is_file(), f"gcc does not find libstdc++.so.6 (it printed {found!r})"
    problems = linux_problems(libstdcxx)
    assert any(p.startswith("needs GLIBC_2.") for p in problems), problems
    assert any(p.startswith("exports _Z") for p in problems), problems
    assert any(p.startswith("does not export fmi2") for p in problems), problems


def test_bundled_parameters_are_the_paper_table(fmu_path):
    params = json.loads(zipfile.ZipFile(fmu_path).read("resources/pacejka87.json"))
    assert params["Fy"]["a8"] == 0.707  # erratum 1
    assert (params["Fy"]["C"], params["Mz"]["C"], params["Fx"]["C"]) == (1.3, 2.4, 1.65)
    assert set(params["Fx"]) == {"C"} | {f"a{i}" for i in range(1, 9)}


def test_documentation_names_every_variable(fmu_path, model_description, fmu3_path, model_description3):
    for path, md in ((fmu_path, model_description), (fmu3_path, model_description3)):
        html = zipfile.ZipFile(path).read("documentation/index.html").decode()
        for v in md.modelVariables:
            assert f'<tr id="var-{v.name}">' in html, (path, v.name)


def test_binaries_hold_no_build_machine_paths(fmu_path):
    # Panic locations name source files: cargo xtask fmu remaps the workspace and cargo's
    # registry to neutral prefixes.
    archive = zipfile.ZipFile(fmu_path)
    for name in ("binaries/linux64/Pacejka87Tire.so", "binaries/win64/Pacejka87Tire.dll"):
        data = archive.read(name)
        for path in (REPO, Path.home()):
            assert bytes(str(path), "utf-8") not in data, f"{name} names {path}"
