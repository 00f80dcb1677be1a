"""Many programmes at once on Dask distributed: one whole diagnosis per task.

Dask schedules, ships and retries the work; this module only submits one task per
programme, gathers the results as they finish and turns a programme that failed into a
failed entry. ``tire-gap-many`` is its command line.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import sys
import time
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import pandas as pd

from . import _native
from ._errors import TireGapError
from ._report import Report

Programme = Union[pd.DataFrame, str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]]

#: The data files a directory may hold, as ``tire-gap diagnose`` reads them.
DATA_SUFFIXES = (".csv", ".tdx", ".dat", ".mat")


@dataclasses.dataclass
class Outcome:
    """One programme of a batch: its report, or the error that stopped it."""

    #: The programme's name: its key in a dict of programmes, else its path (or
    #: ``programme <i>`` for a DataFrame). Its figures and JSON file are named after it.
    name: str
    #: Its position in the batch.
    index: int
    report: Optional[Report] = None
    error: Optional[TireGapError] = None
    #: Wall time of the diagnosis on its worker [s] (0 when the task never ran).
    seconds: float = 0.0
    #: The worker that ran it.
    worker: Optional[str] = None

    @property
    def ok(self) -> bool:
        return self.report is not None

    def summary(self) -> Dict[str, Any]:
        """One row of the batch's table."""
        return {
            "programme": self.name,
            "ok": self.ok,
            "verdict": ",".join(self.report.verdict) if self.report else None,
            "rows": self.report.rows if self.report else None,
            "runs": self.report.runs if self.report else None,
            "seconds": round(self.seconds, 3),
            "error": self.error.message if self.error else None,
        }


def _named(programmes: Union[Sequence[Programme], Mapping[str, Programme]]) -> List[Tuple[str, Programme]]:
    if isinstance(programmes, Mapping):
        return [(str(k), v) for k, v in programmes.items()]
    named = []
    for i, p in enumerate(programmes):
        if isinstance(p, pd.DataFrame):
            named.append((f"programme {i + 1}", p))
        elif isinstance(p, (str, os.PathLike)):
            named.append((os.fspath(p), p))
        else:
            named.append((" ".join(os.fspath(x) for x in p), p))
    return named


def _diagnose_one(
    index: int, name: str, programme: Programme, options: Dict[str, Any], plots: Optional[str]
) -> Outcome:
    """The task: one whole diagnosis on a worker; bad input is a failed outcome."""
    from distributed import get_worker

    from . import diagnose

    try:
        worker = get_worker().address
    except ValueError:
        worker = None
    start = time.perf_counter()
    try:
        report = diagnose(programme, **options)
        if plots is not None:
            report.plots(plots)
        report.__getstate__()  # the text and parameter file, made here
        return Outcome(name, index, report=report, seconds=time.perf_counter() - start, worker=worker)
    except TireGapError as e:
        return Outcome(name, index, error=e, seconds=time.perf_counter() - start, worker=worker)


def file_names(names: Sequence[str]) -> List[str]:
    """The programmes' names as file or directory names, each once: the last part of the
    first path, numbered where two would be the same."""
    def stem(name: str) -> str:
        last = Path(name.split(" ")[0]).name or "programme"
        return "".join(c if c.isalnum() or c in "-_." else "_" for c in last)

    stems = [stem(n) for n in names]
    return [s if stems.count(s) == 1 else f"{i + 1:03d}-{s}" for i, s in enumerate(stems)]


@contextlib.contextmanager
def _client(client: Any, scheduler: Optional[str], workers: int) -> Iterator[Any]:
    """The client given (or one to the address given as ``client``); else one to
    ``scheduler``; else a LocalCluster of ``workers`` processes, one thread each."""
    from distributed import Client, LocalCluster

    if isinstance(client, str):
        client, scheduler = None, client
    if client is not None:
        yield client
    elif scheduler is not None:
        with Client(scheduler) as c:
            yield c
    else:
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster, Client(cluster) as c:
            yield c


def diagnose_as_completed(
    programmes: Union[Sequence[Programme], Mapping[str, Programme]],
    *,
    client: Any = None,
    scheduler: Optional[str] = None,
    workers: int = 2,
    plots_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
    progress: bool = True,
    **options: Any,
) -> Iterator[Outcome]:
    """Diagnoses every programme on Dask, yielding each ``Outcome`` as it finishes.

    Arguments as ``diagnose_many``'s (give ``threads=1`` for its default)."""
    from distributed import as_completed

    named = _named(programmes)
    dirs = file_names([name for name, _ in named])
    with _client(client, scheduler, workers) as c:
        futures = {}
        for index, (name, programme) in enumerate(named):
            if isinstance(programme, pd.DataFrame):
                programme = c.scatter(programme, direct=False)
            plots = None if plots_dir is None else os.path.join(os.fspath(plots_dir), dirs[index])
            future = c.submit(_diagnose_one, index, name, programme, options, plots, pure=False)
            futures[future] = (index, name)
        bar = _bar(len(futures), progress)
        try:
            for future in as_completed(futures):
                index, name = futures[future]
                try:
                    outcome = future.result()
                except Exception as e:  # the task itself failed: a crash, a lost worker
                    outcome = Outcome(
                        name, index, error=TireGapError(f"{type(e).__name__}: {e}", kind="failure")
                    )
                bar.update(1)
                yield outcome
        finally:
            bar.close()
            for future in futures:
                future.cancel()


class _NoBar:
    def update(self, n: int) -> None:
        pass

    def close(self) -> None:
        pass


def _bar(total: int, shown: bool) -> Any:
    if not shown:
        return _NoBar()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc="tire-gap", unit="programme", file=sys.stderr)


def diagnose_many(
    programmes: Union[Sequence[Programme], Mapping[str, Programme]],
    *,
    client: Any = None,
    scheduler: Optional[str] = None,
    workers: int = 2,
    plots_dir: Union[None, str, "os.PathLike[str]"] = None,
    progress: bool = True,
    folds: int = _native.DEFAULT_FOLDS,
    seed: int = _native.DEFAULT_SEED,
    stability_draws: int = _native.DEFAULT_STABILITY_DRAWS,
    effects: Any = None,
    threads: Optional[int] = 1,
) -> List[Outcome]:
    """Diagnoses many programmes at once on Dask distributed, one whole diagnosis per task.

    ``programmes`` is a list (or a dict name -> programme) of what ``tire_gap.diagnose``
    takes: DataFrames, files, directories, or lists of paths. The work runs on ``client`` (a
    ``dask.distributed.Client``, or a scheduler's address such as ``tcp://10.0.0.5:8786``);
    else on a client of ``scheduler`` (an address); else on a LocalCluster of ``workers``
    processes, closed at the end. Paths must be readable where the workers run. Results stream back as they finish,
    with a progress bar (``progress=False`` hides it); with ``plots_dir`` each programme's
    figures go into ``plots_dir/<name>/`` where its worker runs.

    Returns one ``Outcome`` per programme, in the input's order: ``outcome.report`` or, for a
    programme that failed (bad input, a lost worker), ``outcome.error``; a failure loses
    nothing else. The options are ``diagnose``'s, the same for every programme; ``threads``
    is each diagnosis's: 1 by default, so that Dask's workers, one per core, are the
    parallelism (Dask's convention, as its nannies set ``OMP_NUM_THREADS=1``); give more when
    a worker owns several cores, ``None`` for every core of its machine.
    """
    outcomes = list(
        diagnose_as_completed(
            programmes,
            client=client,
            scheduler=scheduler,
            workers=workers,
            plots_dir=plots_dir,
            progress=progress,
            folds=folds,
            seed=seed,
            stability_draws=stability_draws,
            effects=effects,
            threads=threads,
        )
    )
    return sorted(outcomes, key=lambda o: o.index)


def _programmes(paths: Sequence[str], each: bool) -> List[str]:
    """Each path a programme; with ``each``, every data file of a directory its own."""
    found: List[str] = []
    for p in paths:
        path = Path(p)
        if each and path.is_dir():
            files = sorted(f for f in path.iterdir() if f.suffix.lower() in DATA_SUFFIXES and f.is_file())
            if not files:
                raise TireGapError(f"{p}: the directory holds no .csv, .tdx, .dat or .mat file")
            found.extend(os.fspath(f) for f in files)
        else:
            found.append(os.fspath(path))
    return found


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``tire-gap-many``: diagnoses many programmes on Dask and prints one line each."""
    parser = argparse.ArgumentParser(
        prog="tire-gap-many",
        description="Diagnose many tire programmes at once on Dask distributed: each PATH (a "
        "data file, or a directory read as one programme) is one diagnosis.",
    )
    parser.add_argument("paths", nargs="+", metavar="PATH")
    parser.add_argument("--each", action="store_true",
                        help="every data file in a directory is its own programme")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="a running Dask scheduler, e.g. tcp://10.0.0.5:8786 "
                        "(default: a local cluster)")
    parser.add_argument("--workers", type=int, default=2,
                        help="processes of the local cluster (default 2)")
    parser.add_argument("--folds", type=int, default=_native.DEFAULT_FOLDS)
    parser.add_argument("--seed", type=int, default=_native.DEFAULT_SEED)
    parser.add_argument("--stability-draws", type=int, default=_native.DEFAULT_STABILITY_DRAWS)
    parser.add_argument("--effects", help="candidate effects, comma-separated (default: all)")
    parser.add_argument("--threads", type=int, default=1,
                        help="threads per diagnosis (default 1: the workers are the parallelism)")
    parser.add_argument("--json-dir", metavar="DIR",
                        help="write each programme's JSON report as DIR/<name>.json")
    parser.add_argument("--plots-dir", metavar="DIR",
                        help="write each programme's figures into DIR/<name>/")
    parser.add_argument("--summary", metavar="FILE.csv",
                        help="write the batch's table as CSV")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error(f"--workers {args.workers}: at least 1")
    try:
        programmes = _programmes(args.paths, args.each)
    except TireGapError as e:
        print(f"tire-gap-many: {e.message}", file=sys.stderr)
        return 2
    outcomes = diagnose_many(
        programmes,
        scheduler=args.scheduler,
        workers=args.workers,
        plots_dir=args.plots_dir,
        progress=not args.no_progress,
        folds=args.folds,
        seed=args.seed,
        stability_draws=args.stability_draws,
        effects=args.effects,
        threads=args.threads,
    )
    if args.json_dir:
        out = Path(args.json_dir)
        out.mkdir(parents=True, exist_ok=True)
        for o, stem in zip(outcomes, file_names([o.name for o in outcomes])):
            if o.report is not None:
                (out / f"{stem}.json").write_text(o.report.to_json() + "\n")
    table = pd.DataFrame([o.summary() for o in outcomes])
    if args.summary:
        table.to_csv(args.summary, index=False)
    with pd.option_context("display.max_colwidth", 80, "display.width", 200):
        print(table.to_string(index=False))
    failed = [o for o in outcomes if not o.ok]
    for o in failed:
        print(f"tire-gap-many: {o.name}: {o.error.message if o.error else 'failed'}", file=sys.stderr)
    return 3 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
