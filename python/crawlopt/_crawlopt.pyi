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

Numbers = Union[float, list[float]]

class Crawler:
    """A crawler, built as the model file's ``[crawler]`` section (a number stands for every
    link or block)."""

    def __init__(
        self, blocks: int, stiffness: Numbers, mu_forward: Numbers, mu_backward: Numbers
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
    def __eq__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    @staticmethod
    def _from_state(text: str) -> Crawler: ...

class Actuation:
    """An ``[actuation]`` section and the actuation it builds (unbound while every value is a
    single number)."""

    @staticmethod
    def section(
        kind: str,
        period: float,
        amplitude: Optional[Numbers] = None,
        phase_deg: Optional[Numbers] = None,
        mean: Optional[Numbers] = None,
        times: Optional[list[float]] = None,
        lengths: Optional[list[Numbers]] = None,
        links: Optional[int] = None,
    ) -> Actuation: ...
    @staticmethod
    def travelling_wave(
        links: int,
        waveform: Optional[str] = None,
        period: Optional[float] = None,
        amplitude: Optional[float] = None,
        mean: Optional[float] = None,
        lag_deg: Optional[float] = None,
        wavelength: Optional[float] = None,
        direction: Optional[str] = None,
    ) -> Actuation: ...
    def bind(self, links: int) -> Actuation: ...
    @property
    def period(self) -> float: ...
    @property
    def links(self) -> Optional[int]: ...
    @property
    def kind(self) -> str: ...
    def lengths_at(self, t: list[float]) -> list[list[float]]: ...
    def to_toml(self) -> str: ...
    def __eq__(self, other: object) -> bool: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    @staticmethod
    def _from_state(text: str) -> Actuation: ...

class GaitProblem:
    """A ``[gait]`` section posed for a crawler."""

    def __init__(
        self,
        crawler: Crawler,
        period: float,
        max_actuator_speed: Numbers,
        quadratic_weight: Optional[float] = None,
        max_total_variation: Optional[float] = None,
    ) -> None: ...
    def to_json(self) -> str: ...
    @property
    def max_actuator_speed(self) -> Numbers: ...
    def __eq__(self, other: object) -> bool: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    @staticmethod
    def _from_state(text: str) -> GaitProblem: ...

class GaitResult:
    @staticmethod
    def from_json(text: str, name: str = "result") -> GaitResult: ...
    def to_json(self) -> str: ...
    def certify_json(self) -> str: ...
    def figures(self, certified: bool = False) -> list[tuple[str, str, str]]: ...
    def report_html(self, source: str = "crawlopt", conditions: Optional[str] = None) -> str: ...
    def write_report(
        self, path: Union[str, Path], source: str = "crawlopt", conditions: Optional[str] = None
    ) -> None: ...
    def text(self) -> str: ...
    def __eq__(self, other: object) -> bool: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    @staticmethod
    def _from_state(text: str) -> GaitResult: ...

class GeneralProblem:
    @staticmethod
    def from_sections(sections: dict[str, Any]) -> GeneralProblem: ...
    def sections(self) -> dict[str, Any]: ...
    def to_toml(self) -> str: ...
    def __eq__(self, other: object) -> bool: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...
    @staticmethod
    def _from_state(text: str) -> GeneralProblem: ...
    def analyze(self) -> tuple[dict[str, Any], Optional[str]]: ...
    def simulate(
        self,
        method: str,
        steps_per_period: Optional[int],
        max_periods: Optional[int],
        tol: Optional[float],
    ) -> tuple[dict[str, Any], GeneralRecord]: ...
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
        phases: Optional[int] = None,
        patience: Optional[int] = None,
        convergence: bool = False,
        bound: Optional[tuple] = None,
        formulation: Optional[str] = None,
        start: Optional[str] = None,
    ) -> tuple[dict[str, Any], GeneralRecord, list[str]]: ...

class GeneralRecord:
    def figures(self) -> list[tuple[str, str, str]]: ...
    def report_html(self, source: str = "crawlopt") -> str: ...
    def write_report(self, path: Union[str, Path], source: str = "crawlopt") -> None: ...

def load(
    path: Union[str, Path],
) -> tuple[Crawler, Optional[GaitProblem], Optional[Actuation], Optional[list[float]]]: ...
def load_general(path: Union[str, Path]) -> Optional[GeneralProblem]: ...
def read_result(
    text: str, name: str = "result"
) -> Union[GaitResult, tuple[dict[str, Any], GeneralRecord]]: ...
def read_general_result(
    text: str, name: str = "result"
) -> tuple[dict[str, Any], GeneralRecord]: ...
def read_result_file(
    path: Union[str, Path],
) -> Union[GaitResult, tuple[dict[str, Any], GeneralRecord]]: ...
def certify_general_json(text: str, name: str = "result") -> str: ...
def model_toml(
    crawler: Crawler,
    actuation: Optional[Actuation] = None,
    gait: Optional[GaitProblem] = None,
    initial_state: Optional[list[float]] = None,
) -> str: ...
def simulation_figures(
    crawler: Crawler,
    actuation: Actuation,
    method: str,
    steps_per_period: int,
    orbit_state: list[float],
    periods: int,
) -> list[tuple[str, str, str]]: ...
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
    increment_budget: Optional[int] = None,
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
    bound: Optional[tuple[Optional[int], Optional[int], Optional[float], Optional[int]]],
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
