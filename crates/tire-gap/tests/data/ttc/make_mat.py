"""Writes the small TTC run fixtures of tests/ttc.rs: ASCII run files (.dat) and their MATLAB
twins (.mat), made from the same numbers so that both must read to the same data.

    python3 -m venv /tmp/venv-mat && /tmp/venv-mat/bin/pip install numpy scipy
    /tmp/venv-mat/bin/python crates/tire-gap/tests/data/ttc/make_mat.py

The .mat files are what scipy.io.savemat writes (MAT-file level 5, zlib-compressed variables)
laid out as TTC's MATLAB run files: one column per channel, a struct `channel` with cell
arrays `name` and `units`, and the texts `tireid`, `testid` and `source`. The header text,
which holds a creation date, is replaced by a fixed one so the files are reproducible.

B2356run4   SI units, the tab-separated header with `deg c` and `SAE`, a Tire_Name title.
B2356run5   US units (mph, psi, lb, ft-lb, deg F), SR and SL, a free-text title.
B2356run6_nochannel.mat   run 4's columns without the `channel` struct (units unknown).
B2356run7_plain.mat       run 4 without compression (for the mangled-file test).
"""

import os

import numpy as np
import scipy.io

HERE = os.path.dirname(os.path.abspath(__file__))
TIRE = "Hoosier 43075 16x7.5-10 R25B"
HEADER = b"MATLAB 5.0 MAT-file, Platform: GLNXA64, Created by tire-gap tests/data/ttc/make_mat.py"

SA = ["-6.0", "-4.0", "-2.0", "-0.5", "0.5", "2.0", "4.0", "6.0"]
FY = ["1500.2", "1210.4", "701.9", "180.3", "-176.8", "-695.5", "-1204.1", "-1498.6"]
MZ = ["-25.1", "-30.2", "-21.7", "-6.3", "6.1", "21.2", "29.8", "24.9"]
FZ = ["-1112.1", "-1108.7", "-1110.4", "-1115.0", "-1109.9", "-1111.3", "-1113.8", "-1107.6"]


def si_run():
    """Run 4: (names as in the .dat, .mat variable names, units, rows of decimal text)."""
    names = ("ET V N SA IA RL RE P FX FY FZ MX MZ NFX NFY RST TSTI TSTC TSTO AmbTmp SR").split()
    units = ["s", "kph", "rpm", "deg", "deg", "cm", "cm", "kPa", "N", "N", "N", "Nm", "Nm",
             "none", "none", "deg c", "deg c", "deg c", "deg c", "deg c", "SAE"]
    rows = []
    for i in range(8):
        rows.append([f"{0.01 * i:.2f}", "40.2", "385.5", SA[i], "1.0", "22.85", "23.61",
                     "82.74", f"{-12.5 + i:.1f}", FY[i], FZ[i], "3.1", MZ[i], "-0.01", "0.5",
                     "41.2", "45.1", "47.3", "49.5", "23.4", "0.002"])
    return names, [n.upper() for n in names], units, rows


def us_run():
    """Run 5, US units, both slip ratios."""
    names = "ET V N SA IA RL RE P FX FY FZ MX MZ NFX NFY RST TSTI TSTC TSTO AmbTmp SR SL".split()
    units = ["sec", "mph", "rpm", "deg", "deg", "in", "in", "psi", "lb", "lb", "lb", "ft-lb",
             "ft-lb", "none", "none", "deg F", "deg F", "deg F", "deg F", "deg F", "none", "none"]
    rows = []
    for i in range(6):
        rows.append([f"{0.01 * i:.2f}", "25.0", "385.5", SA[i + 1], "0.0", "9.0", "9.3", "12.0",
                     "-2.0", f"{-40.0 * float(SA[i + 1]):.1f}", "-250.0", "2.0",
                     f"{2.5 * float(SA[i + 1]):.2f}", "-0.01", "0.5", "105.0", "113.0",
                     "117.0", "121.0", "75.0", "0.01", "0.012"])
    return names, [n.upper() for n in names], units, rows


def write_dat(path, title, names, units, rows):
    with open(path, "w", newline="\n") as f:
        f.write(title + "\n")
        f.write("\t".join(names) + "\n")
        f.write("\t".join(units) + "\n")
        for r in rows:
            f.write("\t".join(r) + "\n")


def write_mat(path, variables, units, rows, tireid, testid, source, channel=True, compress=True):
    data = {}
    for k, v in enumerate(variables):
        data[v] = np.array([[float(r[k])] for r in rows])
    if channel:
        data["channel"] = {
            "name": np.array([variables], dtype=object),
            "units": np.array([units], dtype=object),
        }
    data["tireid"] = tireid
    data["testid"] = testid
    data["source"] = source
    scipy.io.savemat(path, data, do_compression=compress)
    with open(path, "r+b") as f:
        f.write(HEADER.ljust(116, b" "))


def main():
    names, variables, units, rows = si_run()
    write_dat(os.path.join(HERE, "B2356run4.dat"),
              f"Tire_Name={TIRE}; Rim_Width=7; Run 004", names, units, rows)
    mat_tire = f"{TIRE}, 7 inch rim"
    write_mat(os.path.join(HERE, "B2356run4.mat"), variables, units, rows, mat_tire,
              "Cornering", "B2356run4")
    write_mat(os.path.join(HERE, "B2356run6_nochannel.mat"), variables, units, rows, mat_tire,
              "Cornering", "B2356run6", channel=False)
    write_mat(os.path.join(HERE, "B2356run7_plain.mat"), variables, units, rows, mat_tire,
              "Cornering", "B2356run7", compress=False)

    names, variables, units, rows = us_run()
    write_dat(os.path.join(HERE, "B2356run5.dat"),
              f"{TIRE}, 7 inch rim Run 005", names, units, rows)
    write_mat(os.path.join(HERE, "B2356run5.mat"), variables, units, rows, mat_tire,
              "Cornering", "B2356run5")


if __name__ == "__main__":
    main()
