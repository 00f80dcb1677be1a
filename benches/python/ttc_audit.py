#!/usr/bin/env python3
"""The audit at large: diagnoses Tire Test Consortium run files one by one with `tire-gap` and
writes a table of what each gave: file, round, programme kind, rows, time, verdict, and for
each claim how the test plan moves its driver and where its held-out gain lies (its signature).
The target: no claim whose driver the plan does not move.

Usage (from the repository root, after `cargo build --release`):
    python3 benches/python/ttc_audit.py DIR_OR_FILE... [--binary target/release/tire-gap]
        [--out audit.md] [--json audit.json] [--timeout 1800]
    python3 benches/python/ttc_audit.py --from-json --json audit.json --out audit.md

Each `.mat` and `.dat` file under the given directories (recursively) is diagnosed alone,
largest last; a file that fails is listed with its message. The round is read from the
Calspan project number in the file name (B1464run23 is project 1464, Round 5). Standard
library only. The public TTC run files are not licensed for redistribution: keep them, and
the JSON this writes (their diagnoses in full), out of the repository; the table names files
and verdicts only.
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

# Calspan project numbers of the TTC rounds, as the run files' names carry them.
ROUNDS = {
    "1051": "1-2",
    "1052": "1-2",
    "1175": "3",
    "1320": "4",
    "1464": "5",
    "1654": "6",
    "1965": "8",
    "2356": "9",
}


def round_of(name):
    """The round from a run file's name (`B1464run23.mat` -> 5), else '?'."""
    stem = Path(name).stem.upper()
    for project, rnd in ROUNDS.items():
        if project in stem:
            return rnd
    return "?"


def files_under(paths):
    found = []
    for p in map(Path, paths):
        if p.is_dir():
            found += [f for f in p.rglob("*") if f.suffix.lower() in (".mat", ".dat") and f.is_file()]
        elif p.is_file():
            found.append(p)
    # The smaller first: a long run does not hold up the rest of the table.
    return sorted(set(found), key=lambda f: (f.stat().st_size, str(f)))


def kind_of(report):
    """The programme kind from the blocks the diagnosis found."""
    swept = [b["swept"] for b in report["blocks"]["blocks"]]
    alpha = sum(s in ("alpha", "both") for s in swept)
    kappa = sum(s in ("kappa", "both") for s in swept)
    if kappa and alpha:
        return "mixed"
    if kappa:
        return "drive/brake"
    if alpha:
        return "cornering"
    return "none swept"


def slip_ratio_source(report):
    notes = " ".join(report.get("notes", []))
    if "slip ratio taken as 0" in notes:
        return "free rolling"
    if "read from SL" in notes:
        return "SL"
    if "read from SR" in notes or "SR" in notes:
        return "SR"
    return "-"


def claims_of(report):
    out = []
    for c in report.get("claims", []):
        channels = []
        for ch in c["channels"]:
            s = ch["signature"]
            channels.append(
                "%s %.2g vs %.2g a row, %.2g vs %.2g per run and load (p=%s)"
                % (
                    ch["channel"],
                    s["gain_per_row_active"],
                    s["gain_per_row_idle"],
                    s["run_gain_active"],
                    s["run_gain_idle"],
                    "-" if s["p_value"] is None else "%.1e" % s["p_value"],
                )
            )
        out.append(
            {
                "effect": c["effect"]
                + (" (with %s)" % c["with"] if c.get("with") else "")
                + (" (on split seed %d)" % c["seed"] if c.get("seed") is not None else ""),
                "plan": c["plan"],
                "plan_moves": c["plan_moves"],
                "signature": "; ".join(channels),
            }
        )
    return out


def diagnose(binary, path, timeout):
    start = time.perf_counter()
    try:
        run = subprocess.run(
            [binary, "diagnose", str(path), "--json"], capture_output=True, text=True, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        return None, "timed out after %d s" % timeout, time.perf_counter() - start
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        message = (run.stderr.strip().splitlines() or ["exit %d" % run.returncode])[-1]
        # The table names files, not where they lie on this machine.
        return None, message.replace(str(path), path.name), elapsed
    return json.loads(run.stdout), None, elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="*")
    parser.add_argument("--binary", default=str(REPO / "target" / "release" / "tire-gap"))
    parser.add_argument("--out", default="audit.md", help="the Markdown table")
    parser.add_argument("--json", default=None, help="also every row as JSON here")
    parser.add_argument("--timeout", type=int, default=1800)
    parser.add_argument("--from-json", action="store_true", help="write the table from the JSON of an earlier audit (--json), diagnosing nothing")
    args = parser.parse_args()
    if args.from_json:
        write_markdown(json.loads(Path(args.json).read_text()), args.out)
        return
    rows = []
    files = files_under(args.paths)
    for k, f in enumerate(files, 1):
        report, error, elapsed = diagnose(args.binary, f, args.timeout)
        row = {"file": f.name, "round": round_of(f.name), "time_s": round(elapsed, 1)}
        if report is None:
            row.update(kind="-", rows=0, verdict="failed: " + error, claims=[], slip_ratio="-")
        else:
            row.update(
                kind=kind_of(report),
                rows=report["rows"],
                verdict=", ".join(report["verdict"]) or "(none)",
                claims=claims_of(report),
                slip_ratio=slip_ratio_source(report),
                refused=len(report.get("signature_refusals", [])),
            )
        rows.append(row)
        # The table (and the JSON) so far, so that a long audit stopped part way keeps what it
        # found.
        write_markdown(rows, args.out)
        if args.json:
            Path(args.json).write_text(json.dumps(rows, indent=1))
        print("%d/%d %s: %s (%.0f s)" % (k, len(files), f.name, row["verdict"], elapsed), file=sys.stderr, flush=True)
    write_markdown(rows, args.out)


def verdict_of(row):
    """The effects of a row's verdict (none for a file that failed or named none)."""
    v = row["verdict"]
    if v == "(none)" or v.startswith("failed"):
        return []
    return v.split(", ")


def write_markdown(rows, out):
    lines = [
        "| file | round | kind | slip ratio | rows | time [s] | verdict | claims: driver in the test plan; signature (gain per row where the driver acts vs idle; the same per run over the load's mean square, as the test weighs it) | refused for their signature |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        claims = "<br>".join(
            "%s: %s%s; %s" % (c["effect"], c["plan"], "" if c["plan_moves"] else " **NOT MOVED**", c["signature"])
            for c in r["claims"]
        )
        lines.append(
            "| %s | %s | %s | %s | %s | %.0f | %s | %s | %s |"
            % (r["file"], r["round"], r["kind"], r["slip_ratio"], r["rows"], r["time_s"], r["verdict"], claims or "-", r.get("refused", "-"))
        )
    # An effect is claimed once per file however many rounds and pairs name it.
    by_effect = {}
    unshown = []
    for r in rows:
        claimed = {c["effect"].split(" ")[0] for c in r["claims"]}
        for name in claimed:
            by_effect[name] = by_effect.get(name, 0) + 1
        for name in verdict_of(r):
            if name not in claimed:
                unshown.append("%s in %s" % (name, r["file"]))
    unmoved = sum(not c["plan_moves"] for r in rows for c in r["claims"])
    lines += [
        "",
        "%d files, %d diagnosed, %d effects named (%s) in %d claim entries (one per round or pair "
        "that names an effect); claim entries whose driver the test plan does not move: %d."
        % (
            len(rows),
            sum(r["rows"] > 0 for r in rows),
            sum(by_effect.values()),
            ", ".join("%s %d" % kv for kv in sorted(by_effect.items())) or "none",
            sum(len(r["claims"]) for r in rows),
            unmoved,
        ),
        "",
        "In the verdict without a claim entry (selected on the other fold assignments of the "
        "stability check, not on the first, whose rounds the claims come from): %s."
        % ("; ".join(unshown) or "none"),
    ]
    Path(out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
