"""The one exception tire-gap raises for bad input and failed work."""

from __future__ import annotations

from typing import Optional, Sequence


class TireGapError(Exception):
    """Bad input, or a diagnosis that could not be made.

    The message says what is wrong and, for bad input, where: the same text the command line
    prints. The attributes give the place in parts:

    - ``kind``: ``"input"`` (bad input: the command line's exit code 2), ``"failure"``
      (an output could not be written, or the work failed: exit code 1) or ``"internal"``
      (a bug in tire-gap);
    - ``file``: the file, or ``"DataFrame"`` for a table given in memory;
    - ``line``: the 1-based line of the file at fault, when one line is;
    - ``column``: the column (or TYDEX/TTC channel) at fault;
    - ``rows``: the rows at fault of a DataFrame, as positions from 0 (``df.iloc[rows]``).
    """

    def __init__(
        self,
        message: str,
        *,
        kind: str = "input",
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[str] = None,
        rows: Sequence[int] = (),
    ) -> None:
        super().__init__(message)
        self.message = message
        self.kind = kind
        self.file = file
        self.line = line
        self.column = column
        self.rows = list(rows)

    def __reduce__(self):
        # Keyword arguments survive pickling (results coming back from Dask workers).
        return (_rebuild, (self.message, self.kind, self.file, self.line, self.column, self.rows))


def _rebuild(message, kind, file, line, column, rows):
    return TireGapError(message, kind=kind, file=file, line=line, column=column, rows=rows)
