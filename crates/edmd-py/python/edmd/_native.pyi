from os import PathLike
from typing import Any, Callable, Optional

import numpy as np
import numpy.typing as npt

__version__: str

class Simulation:
    """One replica of a sweep spec, running in this process."""

    @staticmethod
    def from_spec(spec: dict[str, Any] | str, replica: int = 0) -> "Simulation": ...
    @staticmethod
    def load(path: str | PathLike[str], spec: dict[str, Any] | str, replica: int = 0) -> "Simulation": ...
    def save(self, path: str | PathLike[str]) -> None: ...
    def run(
        self,
        tau: Optional[float] = None,
        collisions: Optional[int] = None,
        until_temperature: Optional[float] = None,
    ) -> dict[str, Any]: ...
    def set_rule(
        self,
        eps: Optional[float] = None,
        rule: Optional[dict[str, Any] | str] = None,
        remedy: Optional[dict[str, Any] | str] = None,
    ) -> None: ...
    @property
    def eps(self) -> float: ...
    @property
    def tau(self) -> float: ...
    @property
    def time(self) -> float: ...
    @property
    def temperature(self) -> float: ...
    @property
    def collisions(self) -> int: ...
    @property
    def n(self) -> int: ...
    @property
    def dim(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    @property
    def spins(self) -> npt.NDArray[np.float64]: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def masses(self) -> npt.NDArray[np.float64]: ...
    @property
    def species(self) -> npt.NDArray[np.int64]: ...
    def observe(self, grid: Optional[int] = None) -> dict[str, Any]: ...

def run_sweep_json(
    spec: str,
    out: str | PathLike[str],
    threads: Optional[int] = None,
    force: bool = False,
    shard: Optional[str] = None,
    progress: Optional[Callable[[int, int, int, int], object]] = None,
) -> str: ...
def refine_json(
    out: str | PathLike[str],
    rounds: int = 3,
    budget: Optional[int] = None,
    axes: Optional[list[str]] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int, int, int], object]] = None,
) -> str: ...
