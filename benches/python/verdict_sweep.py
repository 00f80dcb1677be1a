#!/usr/bin/env python3
"""Verdict sweep: synthetic programmes with known effects (each effect alone, pairs, no effect)
on several base tires and seeds, diagnosed by one or more `tire-gap` binaries; prints each
verdict against the truth and how many each binary got right.

Usage (from the repository root, after `cargo build --release`):
    python3 benches/python/verdict_sweep.py --seeds 101 --tires mf52 brush \\
        [--forms physical mf61] [--binaries target/release/tire-gap OTHER_BUILD] [--rows 20000]

A verdict is right when it names exactly the effects the data were made with (in any order);
for the no-effect control, when it is empty. Standard library only.
"""

import argparse
import itertools
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
# Pairs other than the diagnosis suite's (crates/tire-gap/tests/diagnosis.rs).
PAIRS = [
    ("temperature", "inflation_pressure"),
    ("combined_slip", "speed_dependence"),
    ("relaxation_length", "ply_steer_conicity"),
    ("rolling_resistance", "combined_slip"),
]


def effect_names(binary):
    """The candidate effects `binary` tests, read from its `--effects` help (which the tool
    writes from its one list of effect names)."""
    out = subprocess.run([binary, "diagnose", "--help"], capture_output=True, check=True, text=True)
    text = " ".join(out.stdout.split())
    found = re.search(r"comma-separated: (.*?),? or `all`", text)
    if not found:
        raise SystemExit(f"{binary}: no effect list in `diagnose --help`")
    return [name.strip() for name in found.group(1).split(",")]


def diagnose(binary, csv_path):
    start = time.perf_counter()
    out = subprocess.run([binary, "diagnose", csv_path, "--json"], capture_output=True, check=True)
    return json.loads(out.stdout)["verdict"], time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, nargs="+", default=[101])
    parser.add_argument("--tires", nargs="+", default=["mf52", "brush"])
    parser.add_argument("--rows", type=int, default=20_000)
    parser.add_argument(
        "--forms",
        nargs="+",
        default=["physical"],
        help="the forms the effects take in the data (`tire-gap synth --forms`): physical, mf61",
    )
    parser.add_argument("--binaries", nargs="+", default=[str(REPO / "target" / "release" / "tire-gap")])
    args = parser.parse_args()
    cases = [[e] for e in effect_names(args.binaries[0])] + [list(p) for p in PAIRS] + [[]]
    right = [0] * len(args.binaries)
    seconds = [0.0] * len(args.binaries)
    total = 0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in args.seeds:
            for tire, forms in itertools.product(args.tires, args.forms):
                for truth in cases:
                    csv_path = Path(tmp) / "rig.csv"
                    cmd = [args.binaries[0], "synth", "--seed", str(seed), "--rows", str(args.rows)]
                    cmd += ["--tire", tire, "--forms", forms, "--out", str(csv_path)]
                    if truth:
                        cmd += ["--effects", ",".join(truth)]
                    subprocess.run(cmd, check=True, capture_output=True)
                    total += 1
                    line = f"seed {seed} {tire:<6} {forms:<8} {'+'.join(truth) or '(none)':<40}"
                    for k, binary in enumerate(args.binaries):
                        verdict, t = diagnose(binary, csv_path)
                        ok = sorted(verdict) == sorted(truth)
                        right[k] += ok
                        seconds[k] += t
                        line += f" | {'right' if ok else 'WRONG'} {'+'.join(verdict) or '(none)'} ({t:.1f} s)"
                    print(line, flush=True)
    for k, binary in enumerate(args.binaries):
        print(f"{binary}: {right[k]} of {total} right, {seconds[k]:.0f} s of diagnosis")


if __name__ == "__main__":
    sys.exit(main())
