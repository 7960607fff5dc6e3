"""Type stubs of the extension module (Rust, PyO3). The public API is in crawlopt/__init__.py."""

from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np

__version__: str

class InputError(ValueError):
    field: str
    value: Optional[str]

class NonUniqueError(InputError):
    subset: Optional[list[int]]
    forward_sum: float
    backward_sum: float

class InadmissibleError(InputError): ...
class FileError(InputError): ...
class CrawloptError(RuntimeError): ...

class TimeLimitError(CrawloptError):
    incumbent: None

class InfeasibleError(CrawloptError): ...
class NumericalError(CrawloptError): ...

class Crawler:
    def __init__(
        self, stiffness: list[float], mu_forward: list[float], mu_backward: list[float]
    ) -> None: ...
    @property
    def stiffness(self) -> list[float]: ...
    @property
    def mu_forward(self) -> list[float]: ...
    @property
    def mu_backward(self) -> list[float]: ...
    def analyze_json(self) -> str: ...
    def vm(self, rates: list[float]) -> float: ...
    def require_unique(self) -> None: ...

class Actuation:
    @staticmethod
    def wave(
        kind: str, period: float, mean: list[float], amplitude: list[float], phase_deg: list[float]
    ) -> Actuation: ...
    @staticmethod
    def piecewise_linear(
        period: float, times: list[float], lengths: list[list[float]]
    ) -> Actuation: ...
    @property
    def period(self) -> float: ...
    @property
    def links(self) -> int: ...
    def lengths_at(self, t: list[float]) -> list[list[float]]: ...

class GaitProblem:
    def __init__(
        self,
        crawler: Crawler,
        period: float,
        max_actuator_speed: list[float],
        quadratic_weight: Optional[float] = None,
        max_total_variation: Optional[float] = None,
    ) -> None: ...
    def to_json(self) -> str: ...

class GaitResult:
    @staticmethod
    def from_json(text: str, name: str = "result") -> GaitResult: ...
    def to_json(self) -> str: ...
    def certify_json(self) -> str: ...
    def figures(self, certified: bool = False) -> list[tuple[str, str, str]]: ...
    def report_html(self, source: str = "crawlopt") -> str: ...
    def write_report(self, path: Union[str, Path], source: str = "crawlopt") -> None: ...
    def text(self) -> str: ...

class GeneralProblem:
    def analyze(self) -> tuple[dict[str, Any], Optional[str]]: ...
    def simulate(
        self,
        method: str,
        steps_per_period: Optional[int],
        max_periods: Optional[int],
        tol: Optional[float],
    ) -> dict[str, Any]: ...
    def optimize(
        self,
        method: str,
        m: Optional[int],
        shifts: Optional[int],
        time_limit: Optional[float],
        certify: bool,
        progress: Optional[Callable[[str], None]],
        max_phases: Optional[int],
        polish: Optional[bool] = None,
    ) -> dict[str, Any]: ...

def load(
    path: Union[str, Path],
) -> tuple[Crawler, Optional[GaitProblem], Optional[Actuation], Optional[list[float]]]: ...
def load_general(path: Union[str, Path]) -> Optional[GeneralProblem]: ...
def simulate(
    crawler: Crawler,
    actuation: Actuation,
    method: str,
    steps_per_period: Optional[int],
    record_periods: Optional[int],
    max_periods: Optional[int],
    tol: Optional[float],
    accelerate: bool,
    accelerate_after: Optional[int],
    initial_state: Optional[list[float]],
    progress: Optional[Callable[[str], None]],
    newton: bool = True,
) -> tuple[dict[str, Any], dict[str, np.ndarray]]: ...
def optimize(
    crawler: Crawler,
    problem: GaitProblem,
    method: str,
    phases: Optional[int],
    patience: Optional[int],
    max_phases: Optional[int],
    m: Optional[int],
    convergence: bool,
    start: Optional[GaitResult],
    shifts: Optional[int],
    time_limit: Optional[float],
    certify: bool,
    bound: Optional[tuple[Optional[int], Optional[int], Optional[float]]],
    progress: Optional[Callable[[str], None]],
    polish: Optional[bool] = None,
) -> tuple[GaitResult, Optional[str], list[str]]: ...
def fit(
    t: list[float],
    lengths: list[list[float]],
    positions: list[list[float]],
    blocks: int,
    fixes: list[tuple[str, float]],
    noise: Optional[float],
    noise_bound: Optional[float],
    progress: Optional[Callable[[str], Any]],
) -> tuple[dict[str, Any], Optional[np.ndarray]]: ...
def sweep_size(source: str, is_path: bool, base_dir: str) -> tuple[list[str], int]: ...
def sweep_point(source: str, is_path: bool, base_dir: str, id: int) -> str: ...
def sweep_run(source: str, is_path: bool, base_dir: str, threads: int) -> list[str]: ...
