# Type stubs of capz._capz, the compiled module (python/src/capz_py.cpp). Use it through the
# package capz, whose functions check their arguments and carry the documentation.
from typing import Any, Callable, Dict, Iterator, List, Mapping, Optional, Tuple

import numpy as np
import numpy.typing as npt

version: str

class Take:
    """A motion-capture take: positions, gaps, analog, metadata."""

    @property
    def xyz(self) -> npt.NDArray[np.float64]:
        """(frames, points, 3) in the take's units; NaN at gaps; a view of the take."""
    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """(frames, points): False at gaps; a view of the take."""
    @property
    def frames(self) -> int: ...
    @property
    def points(self) -> int: ...
    @property
    def ragged(self) -> bool: ...
    @property
    def total_points(self) -> int: ...
    @property
    def frame_offsets(self) -> npt.NDArray[np.int64]: ...
    @property
    def units_assumed(self) -> bool: ...
    def frame(self, i: int) -> Any: ...
    def iter_frames(self) -> Iterator[Any]: ...
    labels: List[str]
    rate: float
    units: str
    first_frame: int
    @property
    def descriptions(self) -> List[str]: ...
    @property
    def source(self) -> str: ...
    @property
    def format(self) -> str:
        """"c3d", "trc", "pcd-folder" or "unknown"."""
    @property
    def warnings(self) -> List[str]: ...
    @property
    def analog(self) -> npt.NDArray[np.float64]:
        """(samples, channels), the stored numbers; (0, 0) without analog."""
    @property
    def analog_labels(self) -> List[str]: ...
    @analog_labels.setter
    def analog_labels(self, value: List[str]) -> None: ...
    @property
    def analog_rate(self) -> float: ...
    @property
    def analog_samples_per_frame(self) -> int: ...
    @property
    def rotations(self) -> Dict[str, Any]:
        """matrices float32 (samples, segments, 4, 4), reliability, labels, rate, ..."""
    @property
    def attributes(self) -> Dict[str, np.ndarray]:
        """name -> (frames, points) or (frames, points, count) of the field's type."""
    @property
    def parameters(self) -> Dict[str, Dict[str, Any]]:
        """C3D parameter section: group -> parameter -> str, list of str, number or array."""
    def parameter(self, group: str, name: str) -> Optional[Dict[str, Any]]:
        """value, description, type, dims, locked, group_description; None when absent."""
    def set_parameter(
        self, group: str, name: str, value: Any, description: Optional[str] = None
    ) -> None:
        """Sets or adds GROUP:NAME (str, list of str, int, float, array); a take without a
        parameter section first gets the one write() would give it."""
    @property
    def residuals(self) -> Optional[npt.NDArray[np.float32]]:
        """C3D residuals (frames, points), -1 at gaps; None without C3D; a view of the take."""
    @property
    def camera_masks(self) -> Optional[npt.NDArray[np.uint8]]:
        """C3D camera masks (frames, points), 0 at gaps; None without C3D; a view."""
    @property
    def events(self) -> List[Dict[str, Any]]:
        """The C3D EVENT group's events: label, context, time (s), description, subject,
        icon_id, generic_flag."""
    def set_events(self, events: List[Dict[str, Any]]) -> None:
        """Replaces the EVENT group's events (dicts as events gives; time required)."""
    @property
    def header_events(self) -> List[Dict[str, Any]]:
        """The C3D header's event table: label, time (s), display."""
    @property
    def analog_units(self) -> List[str]: ...
    @property
    def analog_physical(self) -> npt.NDArray[np.float64]:
        """(stored - ANALOG:OFFSET) x ANALOG:SCALE x ANALOG:GEN_SCALE, (samples, channels)."""
    @property
    def trc(self) -> Optional[Dict[str, Any]]:
        """TRC: times, frame_numbers, camera_rate, orig_data_rate, ...; None otherwise."""
    @property
    def gap_samples(self) -> int: ...
    def copy(self) -> "Take":
        """A deep copy (nothing shared); copy.copy, copy.deepcopy and pickle work too."""
    def __copy__(self) -> "Take": ...
    def __deepcopy__(self, memo: Dict[int, Any]) -> "Take": ...
    @staticmethod
    def from_arrays(
        xyz: npt.ArrayLike,
        valid: Optional[npt.ArrayLike] = None,
        rate: float = 100.0,
        units: str = "mm",
        labels: Optional[List[str]] = None,
        first_frame: int = 1,
        analog: Optional[npt.ArrayLike] = None,
        analog_rate: float = 0.0,
        analog_labels: Optional[List[str]] = None,
        attributes: Optional[Mapping[str, npt.ArrayLike]] = None,
        rotations: Optional[Mapping[str, Any]] = None,
    ) -> "Take":
        """A Take from numpy arrays (see capz.Take.from_arrays' docstring)."""

DEFAULT_MEMORY_LIMIT: int
AUTO_MEMORY_LIMIT: int

class CapzFile:
    def __init__(self, path: str, memory_limit: int) -> None: ...
    def read_frames(self, first: int, count: Optional[int]) -> Take: ...
    @property
    def info(self) -> Dict[str, Any]: ...
    @property
    def frames(self) -> int: ...
    @property
    def points(self) -> int: ...
    @property
    def path(self) -> str: ...

def take_from_arrays(
    xyz: np.ndarray,
    valid: np.ndarray,
    rate: float,
    units: str,
    labels: List[str],
    first_frame: int,
    analog: Optional[np.ndarray],
    analog_rate: float,
    analog_labels: List[str],
    attributes: List[Tuple[str, str, int, int, np.ndarray]],
    rotations: Optional[Tuple[np.ndarray, np.ndarray, List[str], float]],
) -> Take: ...
def read(
    path: str,
    memory_limit: int,
    progress: Optional[Callable[[int, int], Any]],
    bin_fields: str,
) -> Take: ...
def write(take: Take, path: str, overwrite: bool, pcd_encoding: str, c3d_float: bool, drop_fields: bool, to: str, ply_encoding: str, trc_delimiter: str) -> None: ...
def dropped_by(take: Take, path: str) -> List[str]: ...
def compress(
    take: Take,
    lossless: bool,
    kg_error: Optional[float],
    max_error: Optional[str],
    units: str,
    codec: str,
    clusters: int,
    window: int,
    check: bool,
    codec_options: Dict[str, str],
    threads: int,
    attr_error: Dict[str, float],
    drop_fields: bool,
    analog_max_error: Dict[str, float],
    any_point_order: bool,
    progress: Optional[Callable[[int, int], Any]],
) -> Tuple[bytes, Dict[str, Any]]: ...
def decompress(
    data: Any, name: str, memory_limit: int, progress: Optional[Callable[[int, int], Any]]
) -> Take: ...
def compress_file(
    input: str,
    output: str,
    lossless: bool,
    kg_error: Optional[float],
    max_error: Optional[str],
    units: str,
    codec: str,
    clusters: int,
    window: int,
    check: bool,
    codec_options: Dict[str, str],
    threads: int,
    attr_error: Dict[str, float],
    drop_fields: bool,
    analog_max_error: Dict[str, float],
    any_point_order: bool,
    overwrite: bool,
    progress: Optional[Callable[[int, int], Any]],
    bin_fields: str,
) -> Dict[str, Any]: ...
def compare(a: Take, b: Take) -> Dict[str, Any]: ...
def parse_length(text: str, take_units: str, assume_units: str = "") -> float: ...
def units_to_metres(units: str) -> float: ...
