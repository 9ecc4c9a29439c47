# Signatures of the native module tricell._tricell, for editors and type checkers; the
# docstrings (help(tricell.NeighborList), ...) explain the arguments. test_native.py checks that
# every name, parameter and default here matches the compiled module.
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

__version__: str

Periodic = Union[bool, Sequence[bool]]
Cutoff = Union[float, Dict[Tuple[int, int], float], None]

def backends() -> List[str]: ...

class NeighborList:
    def __init__(
        self,
        cutoff: Cutoff,
        full: bool = True,
        sorted: bool = False,
        threads: int = 1,
        backend: str = "auto",
        max_pairs: int = 500000000,
        grouped: bool = False,
        max_bytes: Optional[int] = None,
        max_neighbors: int = 0,
        tie_tolerance: float = 0.0,
        symmetric: bool = False,
    ) -> None: ...
    def compute(
        self,
        points: ArrayLike,
        box: ArrayLike,
        periodic: Periodic = True,
        quantities: str = "ijSd",
        copy: bool = True,
        radii: Optional[ArrayLike] = None,
        species: Optional[ArrayLike] = None,
        query: Optional[ArrayLike] = None,
    ) -> Union[np.ndarray, Tuple[np.ndarray, ...]]: ...
    def compute_batch(
        self,
        points: Union[ArrayLike, Sequence[ArrayLike]],
        boxes: Union[ArrayLike, Sequence[ArrayLike]],
        periodic: Union[Periodic, Sequence[Periodic]] = True,
        quantities: str = "ijSd",
        batch_ptr: Optional[ArrayLike] = None,
        copy: bool = True,
    ) -> Tuple[np.ndarray, ...]: ...
    @property
    def full(self) -> bool: ...
    @property
    def sorted(self) -> bool: ...
    @property
    def grouped(self) -> bool: ...
    @property
    def max_neighbors(self) -> int: ...
    @property
    def tie_tolerance(self) -> float: ...
    @property
    def symmetric(self) -> bool: ...
    @property
    def threads(self) -> int: ...

class VerletList:
    def __init__(
        self,
        cutoff: float,
        skin: float,
        full: bool = True,
        threads: int = 1,
        max_pairs: int = 500000000,
        max_bytes: Optional[int] = None,
    ) -> None: ...
    def update(
        self,
        points: ArrayLike,
        box: ArrayLike,
        periodic: Periodic = True,
        quantities: str = "ijSd",
    ) -> Union[np.ndarray, Tuple[np.ndarray, ...]]: ...
    @property
    def cutoff(self) -> float: ...
    @property
    def skin(self) -> float: ...
    @property
    def rebuilt(self) -> bool: ...
    @property
    def rebuild_count(self) -> int: ...

class DisplacementTracker:
    def __init__(self, skin: float, cutoff: float) -> None: ...
    def record(self, points: ArrayLike, box: ArrayLike, periodic: Periodic = True) -> None: ...
    def needs_rebuild(self, points: ArrayLike, box: ArrayLike, periodic: Periodic = True) -> bool: ...
    def jumps(
        self, points: ArrayLike, box: ArrayLike, periodic: Periodic = True
    ) -> Optional[np.ndarray]: ...
    def budget(self, box: ArrayLike, periodic: Periodic = True) -> float: ...
    def max_displacement(self, points: ArrayLike, box: ArrayLike, periodic: Periodic = True) -> float: ...
    def reset(self) -> None: ...
    @property
    def recorded(self) -> bool: ...
    @property
    def skin(self) -> float: ...
    @property
    def cutoff(self) -> float: ...

class Rdf:
    def __init__(self, rmax: float, bins: int, threads: int = 1, backend: str = "auto") -> None: ...
    def add_frame(
        self,
        points: ArrayLike,
        box: ArrayLike,
        periodic: Periodic = True,
        species: Optional[ArrayLike] = None,
    ) -> None: ...
    def total(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]: ...
    def partial(self, a: int, b: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]: ...
    @property
    def frames(self) -> int: ...
    @property
    def edges(self) -> np.ndarray: ...
    @property
    def species(self) -> List[int]: ...

def nearest_neighbors(
    points: ArrayLike,
    box: ArrayLike,
    periodic: Periodic = True,
    k: int = 1,
    threads: int = 1,
    backend: str = "auto",
) -> Tuple[np.ndarray, np.ndarray, np.ndarray]: ...
def neighbor_shells(
    points: ArrayLike,
    box: ArrayLike,
    periodic: Periodic,
    cutoffs: Sequence[float],
    quantities: str = "ijSd",
    full: bool = True,
    threads: int = 1,
    copy: bool = True,
) -> Tuple[np.ndarray, ...]: ...
class VerifyReport:
    @property
    def ok(self) -> bool: ...
    @property
    def entries(self) -> int: ...
    @property
    def expected(self) -> int: ...
    @property
    def matched(self) -> int: ...
    @property
    def near_cutoff(self) -> int: ...
    @property
    def missing(self) -> int: ...
    @property
    def extra(self) -> int: ...
    @property
    def duplicates(self) -> int: ...
    @property
    def rule_breaks(self) -> int: ...
    @property
    def wrong_values(self) -> int: ...
    @property
    def reference(self) -> str: ...
    @property
    def message(self) -> str: ...
    def __bool__(self) -> bool: ...

def verify(
    points: ArrayLike,
    box: ArrayLike,
    i: ArrayLike,
    j: ArrayLike,
    S: Optional[ArrayLike] = None,
    d: Optional[ArrayLike] = None,
    D: Optional[ArrayLike] = None,
    *,
    cutoff: Cutoff = None,
    radii: Optional[ArrayLike] = None,
    species: Optional[ArrayLike] = None,
    half: bool = False,
    periodic: Periodic = True,
    threads: int = 1,
    max_pairs: int = 500000000,
    max_bytes: Optional[int] = None,
) -> VerifyReport: ...
def _read(path: str, format: str = "") -> tuple: ...
def _as_array(value: ArrayLike, name: str, rule: str) -> np.ndarray: ...
def _completed_box(box: ArrayLike, periodic: Periodic) -> np.ndarray: ...
