#!/usr/bin/env python3
"""Benchmark: a batch of whole diagnoses one after another in one process, then the same
batch on Dask (tire_gap.diagnose_many) on LocalClusters of 1 and 2 workers, and the
scheduler's overhead per task. `--threads` is each Dask diagnosis's thread count (1, as
diagnose_many's default, or `all`: every core); the sequential diagnoses use every core.

Usage (from the repository root, after scripts/python-env.sh):
    .venv/bin/python benches/python/diagnose_many.py [--programmes 8] [--rows 100000] [--workers 1 2]
        [--threads 1|all]

The programmes are synthetic (tire_gap.synth), each with its own seed and one effect, written
as CSV files that every worker reads itself. The verdicts of every Dask run are checked
against the sequential ones (they must be identical). The overhead is the wall time per task
of 2,000 tasks that do nothing, on a LocalCluster of the largest worker count.
"""

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import tire_gap

EFFECTS = ["temperature", "inflation_pressure", "speed_dependence", "combined_slip"]


def programmes(directory: Path, count: int, rows: int):
    paths = []
    for i in range(count):
        frame = tire_gap.synth(seed=100 + i, effects=[EFFECTS[i % len(EFFECTS)]], rows=rows)
        path = directory / f"tire{i + 1:02d}.csv"
        frame.to_csv(path, index=False)
        paths.append(str(path))
    return paths


def noop(i):
    return i


def overhead(workers: int, tasks: int = 2000) -> float:
    from distributed import Client, LocalCluster, wait

    with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        wait(client.map(noop, range(50), pure=False))  # warm
        start = time.perf_counter()
        wait(client.map(noop, range(tasks), pure=False))
        return (time.perf_counter() - start) / tasks


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--programmes", type=int, default=8)
    parser.add_argument("--rows", type=int, default=100_000)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--threads", default="1", help="threads per Dask diagnosis: N or all")
    args = parser.parse_args()
    threads = None if args.threads == "all" else int(args.threads)
    from distributed import Client, LocalCluster

    print(f"machine: {os.cpu_count()} cores; load average {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        paths = programmes(Path(tmp), args.programmes, args.rows)
        print(f"{args.programmes} programmes of about {args.rows} rows each; "
              f"threads per Dask diagnosis: {args.threads}")
        start = time.perf_counter()
        alone = {}
        for p in paths:
            t = time.perf_counter()
            alone[p] = tire_gap.diagnose(p)
            print(f"  {Path(p).name}: {alone[p].rows} rows, verdict {alone[p].verdict}, "
                  f"{time.perf_counter() - t:.1f} s", flush=True)
        sequential = time.perf_counter() - start
        print(f"sequential, one process: {sequential:.1f} s "
              f"({sequential / len(paths):.1f} s per programme)")
        results = {"sequential_s": sequential}
        for workers in args.workers:
            with LocalCluster(n_workers=workers, threads_per_worker=1,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                start = time.perf_counter()
                outcomes = tire_gap.diagnose_many(paths, client=client, progress=False,
                                                  threads=threads)
                wall = time.perf_counter() - start
            same = all(o.ok and o.report.to_json() == alone[o.name].to_json() for o in outcomes)
            if not same:
                sys.exit(f"{workers} worker(s): a report differs from the sequential one")
            task = sum(o.seconds for o in outcomes) / len(outcomes)
            print(f"diagnose_many, {workers} worker(s): {wall:.1f} s "
                  f"({sequential / wall:.2f}x sequential; a diagnosis took {task:.1f} s on its "
                  f"worker on average); reports identical to the sequential ones")
            results[f"workers_{workers}_s"] = wall
            results[f"workers_{workers}_task_s"] = task
        per_task = overhead(max(args.workers))
        print(f"scheduler overhead: {per_task * 1e3:.2f} ms per no-op task "
              f"({max(args.workers)} workers, 2000 tasks)")
        results["noop_task_ms"] = per_task * 1e3
        print(json.dumps(results))


if __name__ == "__main__":
    main()
