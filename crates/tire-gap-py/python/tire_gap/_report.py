"""The result of a diagnosis: the report's parts as attributes and DataFrames."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

import pandas as pd

from ._errors import TireGapError

PathLike = Union[str, "os.PathLike[str]"]


class Report:
    """A diagnosis of measured tire data against the 1987 Magic Formula.

    The attributes hold the report as the command line's ``--json`` gives it (docs/tire-gap.md
    describes every field); the ``*_df`` properties give its tables as pandas DataFrames.

    - ``verdict``: the effects claimed (list of names, empty when none is).
    - ``gap_unexplained``: the channels whose gap stays unexplained.
    - ``baseline`` / ``baseline_df``: per channel, the 1987 model's held-out RMS error, noise
      floor and gap [N, N.m].
    - ``regions`` / ``regions_df``: the regions holding more than their share of the error.
    - ``rounds`` / ``candidates_df``: every candidate effect tried in every round of forward
      selection, per channel, with its held-out error before and after and its p-value.
    - ``effects`` / ``effects_df``: the first round's candidates against the base model.
    - ``remaining`` / ``remaining_df``: the error left once the verdict's effects are in.
    - ``ceiling`` / ``ceiling_df``: per channel, the held-out error of the 1987 model, of the
      verdict's model and of a complete MF 6.1 fitted on the same folds, and the per-sweep
      floor, with how much of the gap each explains (``words``).
    - ``limitations``, ``notes``, ``untestable``: what could not be tested or estimated, and
      what the reader noticed.
    - ``provenance``: the input, its SHA-256, folds and split seed.

    ``to_json()`` is the command line's ``--json`` output, ``text()`` its text report,
    ``params()`` the fitted FMU parameter set and ``plots(dir)`` writes the figures.
    """

    def __init__(self, native: Any = None, *, state: Optional[Dict[str, Any]] = None) -> None:
        self._native = native
        if native is not None:
            self._json = native.json()
            self._text: Optional[str] = None
            self._params: Optional[str] = None
            self._params_error: Optional[str] = None
        else:
            assert state is not None
            self._json = state["json"]
            self._text = state["text"]
            self._params = state["params"]
            self._params_error = state["params_error"]
        self.data: Dict[str, Any] = json.loads(self._json)
        d = self.data
        self.verdict: List[str] = d["verdict"]
        self.gap_unexplained: List[str] = d["gap_unexplained"]
        self.baseline: List[Dict[str, Any]] = d["baseline"]
        self.regions: List[Dict[str, Any]] = d["regions"]
        self.rounds: List[Dict[str, Any]] = d["rounds"]
        self.effects: List[Dict[str, Any]] = d["effects"]
        self.remaining: List[Dict[str, Any]] = d["remaining"]
        self.ceiling: List[Dict[str, Any]] = d["ceiling"]
        self.limitations: List[Dict[str, Any]] = d["limitations"]
        self.notes: List[str] = d["notes"]
        self.untestable: List[Dict[str, Any]] = d["untestable"]
        self.provenance: Dict[str, Any] = d["provenance"]
        self.rows: int = d["rows"]
        self.runs: int = d["runs"]

    # Tables -----------------------------------------------------------------------------

    def table(self, name: str) -> pd.DataFrame:
        """Any list of the report (``baseline``, ``regions``, ``extrapolation``, ...) as a
        DataFrame, nested fields flattened with ``.`` (``heldout.rms``)."""
        value = self.data.get(name)
        if not isinstance(value, list):
            lists = sorted(k for k, v in self.data.items() if isinstance(v, list))
            raise KeyError(f"the report has no list {name!r}; its lists: {', '.join(lists)}")
        if value and not isinstance(value[0], dict):
            return pd.DataFrame({name: value})
        return pd.json_normalize(value)

    @property
    def baseline_df(self) -> pd.DataFrame:
        """Per channel: held-out RMS [N, N.m], in-sample RMS, noise floor and gap."""
        return self.table("baseline")

    @property
    def regions_df(self) -> pd.DataFrame:
        """The regions of the operating space and their share of the held-out error."""
        return self.table("regions")

    @property
    def remaining_df(self) -> pd.DataFrame:
        """Per channel: the error left with the verdict's effects in."""
        return self.table("remaining")

    @property
    def ceiling_df(self) -> pd.DataFrame:
        """Per channel: held-out RMS of the 1987 model, the verdict's model and the MF 6.1
        reference (``reference.heldout_rms``), the floor (``floor.rms``), and the shares of the
        gap they close."""
        return self.table("ceiling")

    @property
    def effects_df(self) -> pd.DataFrame:
        """The first round's candidates against the base model, one row per effect."""
        return self.table("effects")

    @property
    def candidates_df(self) -> pd.DataFrame:
        """Every candidate of every round, one row per (round, effect, channel)."""
        rows = []
        for number, round_ in enumerate(self.rounds, start=1):
            for trial in round_["trials"]:
                for channel in trial["channels"]:
                    row = {
                        "round": number,
                        "effect": trial["effect"],
                        "selected": trial["effect"] == round_["selected"],
                        "form": trial["form"],
                    }
                    row.update({k: v for k, v in channel.items() if k != "params"})
                    rows.append(row)
        return pd.DataFrame(rows)

    # Outputs ----------------------------------------------------------------------------

    def to_json(self) -> str:
        """The report as one JSON object: what ``tire-gap diagnose --json`` prints."""
        return self._json

    def text(self) -> str:
        """The report as text: what ``tire-gap diagnose`` prints."""
        if self._text is None:
            self._text = self._native.text()
        return self._text

    def _parameter_file(self) -> str:
        if self._params is None and self._params_error is None:
            try:
                self._params = self._native.parameter_file()
            except TireGapError as e:
                self._params_error = e.message
        if self._params is None:
            raise TireGapError(self._params_error or "", kind="failure")
        return self._params

    def params(self, path: Optional[PathLike] = None) -> Dict[str, Any]:
        """The fitted model as the FMU's parameter set (the ``--params`` file's contents);
        written to ``path`` too when given (whole or not at all). Set the FMU's
        ``parameterFile`` to that file. Raises ``TireGapError`` when the FMU would refuse the
        fitted model."""
        text = self._parameter_file()
        if path is not None:
            target = Path(path)
            partial = target.with_name(f".{target.name}.partial")
            partial.write_text(text)
            os.replace(partial, target)
        return json.loads(text)

    def plots(self, directory: PathLike) -> Path:
        """Writes the SVG figures and their ``index.html`` into ``directory`` (created if
        missing) and returns the index page's path."""
        if self._native is None:
            raise TireGapError(
                "the figures are drawn where the diagnosis ran: this report came from another "
                "process; pass plots_dir= to diagnose_many, or diagnose here",
                kind="failure",
            )
        self._native.write_plots(os.fspath(directory))
        return Path(directory) / "index.html"

    # Pickling (reports come back from Dask workers) ----------------------------------------

    def __getstate__(self) -> Dict[str, Any]:
        if self._native is not None:
            self.text()
            try:
                self._parameter_file()
            except TireGapError:
                pass
        return {
            "json": self._json,
            "text": self._text,
            "params": self._params,
            "params_error": self._params_error,
        }

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self.__init__(None, state=state)

    def __repr__(self) -> str:
        verdict = ", ".join(self.verdict) if self.verdict else "none"
        return (
            f"<tire_gap.Report {self.provenance['input']}: {self.rows} rows, {self.runs} runs; "
            f"verdict: {verdict}>"
        )
