"""tire-gap: where the 1987 Magic Formula departs from measured tire data, which unmodelled
effect causes it, and how far the gap shrinks on held-out data once it is added.

- ``diagnose(data, ...)`` diagnoses one programme (a DataFrame, a file, a directory or a
  list of them) and returns a ``Report``.
- ``synth(...)`` makes synthetic rig data with chosen effects, as a DataFrame.
- ``diagnose_many(programmes, client=None, ...)`` diagnoses many programmes at once on Dask
  distributed (needs the ``dask`` extra: ``distributed`` and ``tqdm``).
- ``TireGapError`` is raised for bad input, with the file, line, column and rows at fault.

The numbers are those of the command line ``tire-gap diagnose``: ``Report.to_json()`` is its
``--json`` output. See docs/python.md.
"""

from __future__ import annotations

import os
from typing import Any, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import pandas as pd

from . import _native
from ._errors import TireGapError
from ._report import Report

__all__ = [
    "EFFECTS",
    "Report",
    "TireGapError",
    "diagnose",
    "diagnose_many",
    "diagnose_as_completed",
    "synth",
]
__version__: str = _native.__version__

#: The candidate effects, by the names ``effects=`` takes, in the order they are tested.
EFFECTS: Tuple[str, ...] = tuple(_native.effect_names())

PathLike = Union[str, "os.PathLike[str]"]
Data = Union[pd.DataFrame, PathLike, Sequence[PathLike]]


def _effect_list(effects: Union[None, str, Iterable[str]]) -> Optional[List[str]]:
    if effects is None:
        return None
    if isinstance(effects, str):
        return effects.split(",")
    return [str(e) for e in effects]


def _frame_columns(frame: pd.DataFrame) -> List[Tuple[str, bytes, List[int]]]:
    """Each column as (name, float64 little-endian bytes, rows that are not numbers)."""
    columns = []
    for i, name in enumerate(frame.columns):
        series = frame.iloc[:, i]
        not_numbers: List[int] = []
        if pd.api.types.is_numeric_dtype(series.dtype):
            values = series.to_numpy(dtype="float64", na_value=np.nan)
        else:
            coerced = pd.to_numeric(series, errors="coerce")
            bad = coerced.isna().to_numpy() & series.notna().to_numpy()
            not_numbers = np.flatnonzero(bad).tolist()
            values = coerced.to_numpy(dtype="float64", na_value=np.nan)
        data = np.ascontiguousarray(values, dtype="<f8").tobytes()
        columns.append((str(name), data, not_numbers))
    return columns


def _paths(data: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    if isinstance(data, (str, os.PathLike)):
        return [os.fspath(data)]
    try:
        paths = [os.fspath(p) for p in data]
    except TypeError:
        raise TypeError(
            "data must be a pandas DataFrame, a path, or a list of paths "
            f"(files or directories), not {type(data).__name__}"
        ) from None
    if not paths:
        raise TireGapError("no input: the list of paths is empty")
    return paths


def diagnose(
    data: Data,
    *,
    folds: int = _native.DEFAULT_FOLDS,
    seed: int = _native.DEFAULT_SEED,
    stability_draws: int = _native.DEFAULT_STABILITY_DRAWS,
    effects: Union[None, str, Iterable[str]] = None,
    threads: Optional[int] = None,
) -> Report:
    """Diagnoses the gap between the 1987 Magic Formula and measured tire data.

    ``data`` is one of:

    - a pandas DataFrame with the CSV's columns, units in the names: ``run, t_s, vx_mps,
      fz_N, alpha_deg, kappa, gamma_deg, p_kPa, temp_C, fx_N, fy_N, mz_Nm`` (other units as
      the CSV reader takes them: ``fz_kN``, ``alpha_rad``, ``kappa_pct``, ...; unknown
      columns are ignored with a note);
    - a path to a CSV, TYDEX (``.tdx``) or TTC (``.dat``, ``.mat``) file, or a directory of
      them;
    - a list of such paths, read as one data set of one tire.

    Options, as the command line's: ``folds`` (3..20, whole runs per fold), ``seed`` (the split
    of runs into folds), ``stability_draws`` (1..10 fold assignments that must each select an
    effect), ``effects`` (the candidate effects to test, names from ``tire_gap.EFFECTS`` as a
    list or a comma-separated string; default every one).

    Returns a ``Report``. Raises ``TireGapError`` for bad input (naming the file and line, or
    the DataFrame's column and rows) and for data that cannot support a diagnosis. The work
    runs with the GIL released; Ctrl-C stops it and raises ``KeyboardInterrupt``.

    Example::

        import tire_gap
        rig = tire_gap.synth(seed=3, effects=["temperature"])
        report = tire_gap.diagnose(rig)
        report.verdict            # ['temperature']
        report.baseline_df        # held-out error per channel
    """
    names = _effect_list(effects)
    if threads is not None and int(threads) < 1:
        raise TireGapError(f"threads = {threads} is out of range: at least 1")
    options = (int(folds), int(seed), int(stability_draws), names,
               None if threads is None else int(threads))
    if isinstance(data, pd.DataFrame):
        native = _native.diagnose_columns(_frame_columns(data), "DataFrame", *options)
    else:
        paths = _paths(data)
        native = _native.diagnose_paths(paths, " ".join(paths), *options)
    return Report(native)


def synth(
    *,
    seed: int = 1,
    effects: Union[str, Iterable[str]] = (),
    tire: str = "mf52",
    rows: int = 35_000,
    noise: float = 1.0,
    couple: Optional[str] = None,
    drift: float = 0.0,
    forms: str = "physical",
    out: Optional[PathLike] = None,
    format: str = "csv",
    tydex_units: Optional[str] = None,
) -> pd.DataFrame:
    """Synthetic test-rig data, as ``tire-gap synth`` writes it: the same seed gives the same
    numbers as the command line's CSV.

    - ``seed``: every random choice.
    - ``effects``: effects to switch on (names from ``tire_gap.EFFECTS``, or ``"all"``).
    - ``tire``: the base tire, ``mf87_perturbed``, ``mf52`` or ``brush``.
    - ``rows``: about how many rows, 1000..2000000.
    - ``noise``: sensor-noise multiplier, 0..10.
    - ``couple``: two block conditions that rise and fall together, ``"A:B"``.
    - ``drift``: the fraction of force lost from the first run to the last (wear), 0..0.5.
    - ``forms``: the effects' forms in the true tire, ``"physical"`` (unlike those the
      diagnosis fits) or ``"mf61"`` (MF 6.1's, where it has one).
    - ``out``: also write the data there, as ``tire-gap synth --out``: a CSV file
      (``format="csv"``) or a directory of one ``.tdx`` file per run (``format="tydex"``,
      ``tydex_units`` ``"engineering"`` or ``"si"``); whole or not at all.

    Returns a DataFrame with the CSV's columns (``run``, ``t_s``, ..., ``mz_Nm``); the record
    of what was generated (tire, effects, magnitudes) is in ``frame.attrs["truth"]``.
    """
    import json

    columns, truth = _native.synth(
        {
            "seed": int(seed),
            "effects": _effect_list(effects) or [],
            "tire": str(tire),
            "rows": int(rows),
            "noise": float(noise),
            "couple": couple,
            "drift": float(drift),
            "forms": str(forms),
            "out": None if out is None else os.fspath(out),
            "format": str(format),
            "tydex_units": tydex_units,
        }
    )
    frame = pd.DataFrame({name: np.frombuffer(data, dtype="<f8") for name, data in columns})
    frame["run"] = frame["run"].astype("int64")
    frame.attrs["truth"] = json.loads(truth)
    return frame


def __getattr__(name: str) -> Any:
    # The Dask side loads only when used: dask and distributed are an optional extra.
    if name in ("diagnose_many", "diagnose_as_completed", "Outcome"):
        from . import _many

        return getattr(_many, name)
    raise AttributeError(f"module 'tire_gap' has no attribute {name!r}")
