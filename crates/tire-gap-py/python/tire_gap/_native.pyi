"""The compiled part of tire_gap (Rust): use the functions of ``tire_gap`` instead."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

__version__: str
DEFAULT_FOLDS: int
DEFAULT_SEED: int
DEFAULT_STABILITY_DRAWS: int

class Diagnosis:
    """A finished diagnosis."""

    def json(self) -> str: ...
    def text(self) -> str: ...
    def parameter_file(self) -> str: ...
    def write_plots(self, dir: str) -> List[str]: ...

def diagnose_paths(
    paths: Sequence[str],
    shown: str,
    folds: int,
    seed: int,
    stability_draws: int,
    effects: Optional[Sequence[str]] = None,
    threads: Optional[int] = None,
) -> Diagnosis: ...
def diagnose_columns(
    columns: Sequence[Tuple[str, bytes, Sequence[int]]],
    source: str,
    folds: int,
    seed: int,
    stability_draws: int,
    effects: Optional[Sequence[str]] = None,
    threads: Optional[int] = None,
) -> Diagnosis: ...
def synth(options: Dict[str, Any]) -> Tuple[List[Tuple[str, bytes]], str]: ...
def effect_names() -> List[str]: ...
