"""capz: compression of capture takes (C3D, TRC, PCD / PLY / .bin frames), numpy in and out.

    take = capz.read("walk.c3d")                  # also .trc, PCD / PLY / .bin frames, a .capz
    data = capz.compress(take, max_error="0.1mm")  # bytes
    back = capz.decompress(data)                   # a Take
    capz.compress_file("walk.c3d", "walk.capz")    # the same bytes as `capz compress`

A Take's arrays (xyz, valid, analog, attributes) are numpy views of its storage. Every
function raises capz.Error on failure. See docs/PYTHON.md.
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Callable, Dict, Iterator, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _capz
from ._capz import Take
from ._error import Error

__all__ = [
    "Error",
    "Take",
    "Frame",
    "CapzFile",
    "read",
    "write",
    "compress",
    "decompress",
    "compress_file",
    "open",
    "compare",
    "DEFAULT_MEMORY_LIMIT",
]
__version__: str = _capz.version

PathLike = Union[str, "os.PathLike[str]"]
Length = Union[str, float, int]

# PCD field types numpy can hold: dtype kind -> PCD type letter.
_ATTRIBUTE_KINDS = {"f": "F", "u": "U", "i": "I"}


def _invalid(message: str) -> Error:
    return Error("invalid-parameter", message, 6)


def _path(p: PathLike, what: str) -> str:
    try:
        return os.fspath(p)
    except TypeError:
        raise _invalid(f"{what} must be a path (str or os.PathLike), got {type(p).__name__}")


def _length(value: Optional[Length], what: str) -> Optional[str]:
    """A length as the library parses it: "0.1mm", "2 cm", or a number in the take's units."""
    if value is None:
        return None
    if isinstance(value, str):
        return value
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        return repr(float(value))
    raise _invalid(f"{what} must be a length such as '0.1mm' or a number, got {value!r}")


def _kg(value: Optional[float]) -> Optional[float]:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise _invalid(f"kg_error must be a number (percent), got {value!r}")
    return float(value)


def _options(codec_options: Optional[Mapping[str, Any]]) -> Dict[str, str]:
    if codec_options is None:
        return {}
    if not isinstance(codec_options, Mapping):
        raise _invalid("codec_options must be a dict of key -> value")
    return {str(k): str(v) for k, v in codec_options.items()}


def _coding(max_error: Optional[Length], lossless: bool, kg_error: Optional[float],
            units: Optional[str], codec: str, clusters: int, window: int, check: bool,
            codec_options: Optional[Mapping[str, Any]], threads: int = 1,
            attr_error: Optional[Mapping[str, float]] = None, drop_fields: bool = False,
            analog_max_error: Optional[Mapping[str, float]] = None,
            point_order: str = "kept") -> tuple:
    """The target and coding options of compress() and compress_file(), checked, in the order
    _capz.compress and _capz.compress_file take them."""
    if not isinstance(threads, (int, np.integer)) or isinstance(threads, bool) or threads < 0:
        raise _invalid(f"threads must be an int >= 0 (0: every core), got {threads!r}")
    bounds = {}
    for k, v in (attr_error or {}).items():
        if not isinstance(k, str) or isinstance(v, bool) or not isinstance(v, (int, float, np.floating)):
            raise _invalid(f"attr_error wants field name -> bound, got {k!r}: {v!r}")
        bounds[k] = float(v)
    analog = {}
    for k, v in (analog_max_error or {}).items():
        if not isinstance(k, str) or isinstance(v, bool) or not isinstance(v, (int, float, np.floating)):
            raise _invalid(f"analog_max_error wants channel label or unit -> bound, got {k!r}: {v!r}")
        analog[k] = float(v)
    if point_order not in ("kept", "any"):
        raise _invalid(f"point_order must be 'kept' or 'any', got {point_order!r}")
    return (bool(lossless), _kg(kg_error), _length(max_error, "max_error"), units or "",
            str(codec), int(clusters), int(window), bool(check), _options(codec_options),
            int(threads), bounds, bool(drop_fields), analog, point_order == "any")


def _array(name: str, value: Any, dtype: Optional[np.dtype] = None) -> np.ndarray:
    """`value` as an ndarray without conversion; a wrong dtype is an error, not a cast."""
    a = np.asarray(value)
    if dtype is not None and a.dtype != dtype:
        raise _invalid(
            f"{name} must be {np.dtype(dtype).name}, got {a.dtype.name}"
            f" (convert it with .astype(np.{np.dtype(dtype).name}))"
        )
    return a


def _first_bad(mask: np.ndarray) -> Tuple[int, ...]:
    return tuple(int(i) for i in np.argwhere(mask)[0])


def _from_arrays(
    xyz: Any,
    valid: Any = None,
    rate: float = 100.0,
    units: str = "mm",
    labels: Optional[Sequence[str]] = None,
    first_frame: int = 1,
    analog: Any = None,
    analog_rate: float = 0.0,
    analog_labels: Optional[Sequence[str]] = None,
    attributes: Optional[Mapping[str, Any]] = None,
    rotations: Optional[Mapping[str, Any]] = None,
) -> Take:
    """A Take from numpy arrays.

    xyz           float64 (frames, points, 3), in `units`. Gap samples may hold anything.
    valid         bool (frames, points): False marks a gap. None: a sample is a gap where its
                  coordinates are NaN (all three or some); infinite values are an error.
                  A valid sample must hold finite coordinates.
    rate          frames per second (0: unknown).
    units         "mm", "cm", "m", ... or "" (unknown; a bound with a unit then needs
                  compress(..., units=...)).
    labels        one string per point (default: empty strings).
    first_frame   number of the first frame.
    analog        float64 (samples, channels), samples a multiple of frames; analog_rate in Hz
                  and analog_labels (one per channel) go with it.
    attributes    dict name -> array (frames, points) or (frames, points, count) of float32,
                  float64, uint8/16/32/64 or int8/16/32/64 (per-point fields, as PCD has).
    rotations     dict as Take.rotations gives it: matrices float32 (samples, segments, 4, 4)
                  indexed [sample, segment, row, column], reliability float32
                  (samples, segments), labels (one per segment), rate (Hz); samples a
                  multiple of frames.

    xyz, valid, analog and attributes are copied once into the take (no copy before that when
    they are C-contiguous).
    """
    if isinstance(xyz, (list, tuple)):
        return _from_frames(xyz, valid, rate, units, labels, first_frame, analog, attributes,
                            rotations)
    a = _array("xyz", xyz, np.dtype(np.float64))
    if a.ndim != 3 or a.shape[2] != 3:
        raise _invalid(f"xyz must have shape (frames, points, 3), got {a.shape}")
    frames, points = a.shape[0], a.shape[1]
    if valid is None:
        nan = np.isnan(a)
        if np.isinf(a).any():
            f, p, _ = _first_bad(np.isinf(a))
            raise _invalid(f"xyz[{f}, {p}] is infinite (mark gaps with NaN or pass valid=)")
        v = ~nan.any(axis=2)
    else:
        v = _array("valid", valid, np.dtype(np.bool_))
        if v.shape != (frames, points):
            raise _invalid(f"valid must have shape {(frames, points)}, got {v.shape}")
        bad = v & ~np.isfinite(a).all(axis=2)
        if bad.any():
            f, p = _first_bad(bad)
            raise _invalid(f"xyz[{f}, {p}] is marked valid but is not a finite number")
    _check_rate_units(rate, units)
    label_list = _labels("labels", labels, points)
    an = None
    if analog is not None:
        an = _array("analog", analog, np.dtype(np.float64))
        if an.ndim != 2:
            raise _invalid(f"analog must have shape (samples, channels), got {an.shape}")
        if an.shape[1] > 0 and (frames == 0 or an.shape[0] == 0 or an.shape[0] % frames):
            raise _invalid(
                f"analog has {an.shape[0]} samples: a positive multiple of the {frames} frames "
                "is needed"
            )
        if not np.isfinite(an).all():
            raise _invalid("analog holds NaN or infinite values")
        if not (np.isfinite(analog_rate) and analog_rate >= 0):
            raise _invalid(f"analog_rate must be a finite number >= 0, got {analog_rate!r}")
        an = np.ascontiguousarray(an)
    channel_labels = _labels("analog_labels", analog_labels, an.shape[1] if an is not None else 0)
    attrs: List[tuple] = []
    for name, value in (attributes or {}).items():
        if not isinstance(name, str) or not name:
            raise _invalid(f"attribute names must be non-empty strings, got {name!r}")
        arr = np.asarray(value)
        kind = _ATTRIBUTE_KINDS.get(arr.dtype.kind)
        if kind is None or arr.dtype.itemsize not in (1, 2, 4, 8) or arr.dtype == np.float16:
            raise _invalid(
                f"attribute '{name}': dtype {arr.dtype} is not a PCD field type (float32, "
                "float64, uint8..uint64, int8..int64)"
            )
        if arr.ndim not in (2, 3) or arr.shape[:2] != (frames, points):
            raise _invalid(
                f"attribute '{name}' must have shape ({frames}, {points}) or "
                f"({frames}, {points}, count), got {arr.shape}"
            )
        count = arr.shape[2] if arr.ndim == 3 else 1
        if count < 1:
            raise _invalid(f"attribute '{name}': count must be >= 1")
        little = arr.dtype.newbyteorder("<")
        arr = np.ascontiguousarray(arr, dtype=little)  # no copy when already little-endian
        attrs.append((name, kind, arr.dtype.itemsize, count, arr))
    rot = _rotations(rotations, frames)
    return _capz.take_from_arrays(
        np.ascontiguousarray(a),
        np.ascontiguousarray(v).view(np.uint8),
        float(rate),
        units,
        label_list,
        int(first_frame),
        an,
        float(analog_rate),
        channel_labels,
        attrs,
        rot,
    )


def _check_rate_units(rate: Any, units: Any) -> None:
    if isinstance(rate, bool) or not isinstance(rate, (int, float, np.integer, np.floating)):
        raise _invalid(f"rate must be a number, got {rate!r}")
    if not (np.isfinite(rate) and rate >= 0):
        raise _invalid(f"rate must be a finite number >= 0, got {rate!r}")
    if not isinstance(units, str):
        raise _invalid(f"units must be a string, got {units!r}")
    if units and _capz.units_to_metres(units) == 0:
        raise _invalid(f"units: unknown unit '{units}' (mm, cm, m, in, ...)")


def _from_frames(xyz: Sequence[Any], valid: Any, rate: float, units: str,
                 labels: Optional[Sequence[str]], first_frame: int, analog: Any,
                 attributes: Optional[Mapping[str, Any]], rotations: Any) -> Take:
    """Take.from_arrays for a list of frames, each (points_f, 3): a ragged take."""
    if labels is not None or analog is not None or rotations is not None:
        raise _invalid("a take from a list of frames has no labels, analog or rotations")
    frames = [_array(f"xyz[{i}]", f, np.dtype(np.float64)) for i, f in enumerate(xyz)]
    for i, f in enumerate(frames):
        if f.ndim != 2 or f.shape[1] != 3:
            raise _invalid(f"xyz[{i}] must have shape (points, 3), got {f.shape}")
    counts = [f.shape[0] for f in frames]
    offsets = np.zeros(len(frames) + 1, np.int64)
    offsets[1:] = np.cumsum(counts, dtype=np.int64)
    flat = np.concatenate(frames) if frames else np.zeros((0, 3))
    if valid is None:
        if np.isinf(flat).any():
            i = int(np.argwhere(np.isinf(flat))[0][0])
            raise _invalid(f"point {i} of the flattened frames is infinite (mark gaps with NaN "
                           "or pass valid=)")
        v = ~np.isnan(flat).any(axis=1)
    else:
        if not isinstance(valid, (list, tuple)) or len(valid) != len(frames):
            raise _invalid("valid: one bool array per frame expected")
        parts = [_array(f"valid[{i}]", x, np.dtype(np.bool_)) for i, x in enumerate(valid)]
        for i, x in enumerate(parts):
            if x.shape != (counts[i],):
                raise _invalid(f"valid[{i}] must have shape ({counts[i]},), got {x.shape}")
        v = np.concatenate(parts) if parts else np.zeros(0, np.bool_)
        bad = v & ~np.isfinite(flat).all(axis=1)
        if bad.any():
            raise _invalid(f"point {int(np.argwhere(bad)[0][0])} of the flattened frames is "
                           "marked valid but is not a finite number")
    _check_rate_units(rate, units)
    attrs: List[tuple] = []
    for name, value in (attributes or {}).items():
        if not isinstance(name, str) or not name:
            raise _invalid(f"attribute names must be non-empty strings, got {name!r}")
        if not isinstance(value, (list, tuple)) or len(value) != len(frames):
            raise _invalid(f"attribute '{name}': one array per frame expected")
        parts = [np.asarray(x) for x in value]
        arr = np.concatenate(parts) if parts else np.zeros(0, np.float32)
        kind = _ATTRIBUTE_KINDS.get(arr.dtype.kind)
        if kind is None or arr.dtype.itemsize not in (1, 2, 4, 8) or arr.dtype == np.float16:
            raise _invalid(f"attribute '{name}': dtype {arr.dtype} is not a PCD field type")
        for i, x in enumerate(parts):
            if x.ndim not in (1, 2) or x.shape[0] != counts[i] or x.dtype != arr.dtype:
                raise _invalid(f"attribute '{name}'[{i}] must have shape ({counts[i]},) or "
                               f"({counts[i]}, count) and one dtype, got {x.shape} {x.dtype}")
        count = arr.shape[1] if arr.ndim == 2 else 1
        if count < 1:
            raise _invalid(f"attribute '{name}': count must be >= 1")
        arr = np.ascontiguousarray(arr, dtype=arr.dtype.newbyteorder("<"))
        attrs.append((name, kind, arr.dtype.itemsize, count, arr))
    return _capz.take_from_frames(np.ascontiguousarray(flat), np.ascontiguousarray(v).view(np.uint8),
                                  offsets, float(rate), units, int(first_frame), attrs)


class Frame(NamedTuple):
    """One frame of a take: views of its storage (writing to them changes the take)."""

    xyz: np.ndarray  # float64 (points, 3)
    valid: np.ndarray  # bool (points,)
    attributes: Dict[str, np.ndarray]  # name -> (points,) or (points, count)


def _frame(self: Take, i: int) -> Frame:
    """Frame i (negative counts from the end) as views: the same for fixed and ragged takes."""
    n = self.frames
    if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -n <= i < n:
        raise IndexError(f"frame {i!r} of a take of {n} frames")
    i = int(i) % n
    if not self.ragged:
        return Frame(self.xyz[i], self.valid[i], {k: v[i] for k, v in self.attributes.items()})
    o = self.frame_offsets
    b, e = int(o[i]), int(o[i + 1])
    return Frame(self.xyz[b:e], self.valid[b:e], {k: v[b:e] for k, v in self.attributes.items()})


def _iter_frames(self: Take) -> Iterator[Frame]:
    """Every frame in order, as Take.frame(i) gives it."""
    for i in range(self.frames):
        yield _frame(self, i)


def _rotations(rotations: Optional[Mapping[str, Any]], frames: int) -> Optional[tuple]:
    """Take.rotations' dict checked, matrices laid out column-major as the library keeps them."""
    if rotations is None:
        return None
    if not isinstance(rotations, Mapping) or "matrices" not in rotations:
        raise _invalid("rotations must be a dict with matrices, reliability, labels and rate")
    m = _array("rotation matrices", rotations["matrices"], np.dtype(np.float32))
    if m.ndim != 4 or m.shape[2:] != (4, 4):
        raise _invalid(f"rotation matrices must have shape (samples, segments, 4, 4), got {m.shape}")
    samples, segments = m.shape[0], m.shape[1]
    if segments and (frames == 0 or samples == 0 or samples % frames):
        raise _invalid(f"rotations have {samples} samples: a positive multiple of the {frames} "
                       "frames is needed")
    rel = rotations.get("reliability")
    rel = np.ones((samples, segments), np.float32) if rel is None else \
        _array("rotation reliability", rel, np.dtype(np.float32))
    if rel.shape != (samples, segments):
        raise _invalid(f"rotation reliability must have shape {(samples, segments)}, "
                       f"got {rel.shape}")
    labels = _labels("rotation labels", rotations.get("labels"), segments)
    rate = float(rotations.get("rate", 0.0))
    column_major = np.ascontiguousarray(m.transpose(0, 1, 3, 2)).reshape(samples, segments, 16)
    return (column_major, np.ascontiguousarray(rel), labels, rate)


def _labels(what: str, labels: Optional[Sequence[str]], n: int) -> List[str]:
    if labels is None:
        return [""] * n
    if isinstance(labels, str) or not all(isinstance(s, str) for s in labels):
        raise _invalid(f"{what} must be a list of strings")
    out = list(labels)
    if len(out) != n:
        raise _invalid(f"{what}: {n} expected, got {len(out)}")
    return out


Take.from_arrays = staticmethod(_from_arrays)  # type: ignore[attr-defined]
Take.frame = _frame  # type: ignore[attr-defined]
Take.iter_frames = _iter_frames  # type: ignore[attr-defined]


DEFAULT_MEMORY_LIMIT: int = _capz.DEFAULT_MEMORY_LIMIT
"""The decoder's memory limit in bytes by default (4 GiB; more for an archive above 4 MiB, 1024
bytes per byte of it): see read()'s memory_limit."""


def _memory_limit(v: Optional[int]) -> int:
    if v is None:
        return _capz.AUTO_MEMORY_LIMIT
    if isinstance(v, bool) or not isinstance(v, int) or v < 0 or v >= _capz.AUTO_MEMORY_LIMIT:
        raise _invalid(f"memory_limit must be a number of bytes >= 0 (0: none), got {v!r}")
    return v


def read(
    path: PathLike,
    *,
    memory_limit: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    bin_fields: Optional[str] = None,
) -> Take:
    """Reads a take: a .c3d, a .trc, a .pcd / .ply / .bin frame or a folder of them, or a .capz
    (decompressed). A folder whose frames have different point counts (LiDAR sweeps) gives a
    ragged take: xyz (total points, 3) with frame_offsets, and frame(i) / iter_frames() views.
    bin_fields: the record of .bin frames other than KITTI's or nuScenes' (the CLI's
    --bin-fields), as "x y z intensity ring:U2 t:F8" (TYPE F4 F8 U1 U2 U4 U8 I1 I2 I4 I8, F4
    when none; "_" for padding).

    Gaps read as valid == False and NaN in xyz. Raises capz.Error naming the file and fault.
    memory_limit: for a .capz, the most bytes of decoded samples it may ask for (None: 4 GiB,
    DEFAULT_MEMORY_LIMIT, or 1024 bytes per byte of the archive when that is more; 0: no limit);
    a stream asking for more raises capz.Error with code "memory-limit" before anything is
    allocated (the CLI's --memlimit). progress(frames_done, frames_total) is called after each
    window decoded of a .capz, and after each block of up to 64 frames read of other inputs;
    Ctrl-C (or an exception progress raises) stops the reading at the end of the window or block
    at hand.
    """
    return _capz.read(_path(path, "path"), _memory_limit(memory_limit), progress,
                      bin_fields or "")


def write(
    take: Take,
    path: PathLike,
    *,
    overwrite: bool = False,
    pcd_encoding: str = "",
    c3d_float: bool = False,
    drop_fields: bool = False,
    to: str = "",
    ply_encoding: str = "",
    trc_delimiter: str = "",
) -> None:
    """Writes a take by the output path: ".c3d", ".trc", ".pcd", ".ply", ".bin" (one frame
    file), otherwise a folder of frames: of format `to` ("pcd", "ply", "bin"; "": the take's own
    when it came from PCD, PLY or .bin frames, else PCD). ply_encoding: "ascii",
    "binary_little_endian" or "binary_big_endian" ("": the source's, else little-endian).
    trc_delimiter (the CLI's --trc-delimiter): a TRC's "tab" (OpenSim's form) or "comma" (the
    form pyomeca and spreadsheets write: every line padded with commas to the widest); "": the
    take's own, so a take read from a comma-separated TRC, or from the archive of one, is
    written with commas, any other with tabs (`capz convert` writes tabs unless asked).

    The output appears whole or not at all. overwrite: replace an existing output (the CLI's
    -f). pcd_encoding: "ascii", "binary" or "binary_compressed" ("": the source folder's, else
    binary). c3d_float: write a C3D as float even when the source was int16. drop_fields: a take
    with PCD fields (attributes) written to C3D or TRC, which cannot hold them, leaves them out;
    without it that is an Error naming them. What else the format cannot hold (analog
    channels, the C3D parameter section and its events, rotations in TRC or PCD; the frame rate
    in PCD) is left out with a UserWarning naming it. Use compress()/compress_file() for .capz.
    """
    p = _path(path, "path")
    if p.lower().endswith(".capz"):
        raise Error("usage", f"{p}: write() writes C3D, TRC and PCD; use compress_file() or "
                    "compress() for .capz", 1)
    _check_take(take)
    dropped = _capz.dropped_by(take, p)
    _capz.write(take, p, bool(overwrite), pcd_encoding, bool(c3d_float), bool(drop_fields),
                str(to), str(ply_encoding), str(trc_delimiter))
    if dropped:
        warnings.warn(f"{p} does not keep {', '.join(dropped)}", UserWarning, stacklevel=2)


def _check_take(take: Any) -> None:
    if not isinstance(take, Take):
        raise _invalid(f"expected a capz.Take, got {type(take).__name__}")


def _check_positions(take: Take) -> None:
    """A valid sample must hold finite coordinates (the arrays are writeable views)."""
    bad = take.valid & ~np.isfinite(take.xyz).all(axis=-1)
    if bad.any():
        f, p = _first_bad(bad)
        raise _invalid(f"xyz[{f}, {p}] is marked valid but is not a finite number")


def compress(
    take: Take,
    *,
    max_error: Optional[Length] = None,
    lossless: bool = False,
    kg_error: Optional[float] = None,
    codec: str = "none",
    codec_options: Optional[Mapping[str, Any]] = None,
    clusters: int = 0,
    window: int = 0,
    check: bool = True,
    units: Optional[str] = None,
    stats: bool = False,
    threads: int = 1,
    attr_error: Optional[Mapping[str, float]] = None,
    drop_fields: bool = False,
    analog_max_error: Optional[Mapping[str, float]] = None,
    point_order: str = "kept",
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Union[bytes, Tuple[bytes, Dict[str, Any]]]:
    """Compresses a take to .capz bytes (`capz compress` on a take in memory).

    Error bounds are per coordinate: every valid coordinate comes back within the bound (a
    point's Euclidean error is then at most sqrt(3) times it). Gaps, analog channels (unless
    analog_max_error bounds them), labels, rate, units, C3D parameters and events come back
    exactly. Give at most one target:

    max_error      per-coordinate bound: a length with a unit ("0.1mm", "0.05cm", "0.0001m",
                   "0.01in") or a number in the take's own units. Default "0.1mm"; for a take
                   without units (PCD, unless units= is given) 1e-4 x the bounding-box
                   diagonal of the data (a few points far outside the others do not count:
                   a UserWarning then says so, as the CLI's note), and a bound with a unit
                   needs units=.
    kg_error       instead of a bound: KG error target in percent; the grid is chosen so the
                   achieved KG error is at or just under it.
    lossless       every stored coordinate back exactly (int16 C3D integers, float32 bits,
                   TRC decimals).

    codec          transform stage in front of the coder: "none" (temporal prediction only),
                   a transform codec built in ("ts", "pdct"), or "auto" (tries each, keeps the
                   smallest; encoding takes about as long as all of them together).
    codec_options  dict of codec option key -> value (the CLI's --codec-opt key=value).
    clusters       clusters for the transform codec (0 = its default, -1 = search).
    window         frames per independently decodable window, 1..8192; 0: 1024, or with codec
                   none up to 8192 for takes of fewer than 64 points.
    check          decode each window after writing it and verify the bound (False: the CLI's
                   --no-check; a take of ragged frames then has NaN in its stats' error:
                   not measured).
    units          units of a take that has none (or whose units capz cannot read): mm, cm, m.
    stats          also return the report as a dict: (bytes, stats).
    threads        windows coded in parallel (the CLI's -T; 0: every core); the bytes do not
                   depend on it.
    attr_error     dict field name -> bound for float point fields (PCD attributes), in the
                   field's units; a name also bounds every field NAME_* ("normal"). The CLI's
                   --attr-error. Fields not named are lossless; a bounded field is kept
                   exact in each window where that codes no larger.
    drop_fields    leave the point fields out of the archive (the CLI's --drop-fields).
    analog_max_error  dict channel label or unit -> bound for analog channels, in the
                   channel's physical units (after ANALOG:SCALE, GEN_SCALE and OFFSET), e.g.
                   {"N": 0.05, "Nmm": 5, "V": 1e-5} or {"Fz1": 0.1}; a label wins over its
                   unit. The CLI's --analog-max-error. Channels not named stay lossless; not
                   with lossless=True. A key that names no channel is a UserWarning.
    point_order    "kept" (default) or "any": the archive may reorder the points of each frame
                   of a scan (frames of their own point counts, or one sweep), each with its
                   fields, gaps after the valid points, and decodes in that order (the CLI's
                   --point-order; not with lossless=True).
    progress       called as progress(frames_done, frames_total) after each window (a window
                   is up to `window` frames); an exception it raises stops the coding and is
                   raised here.

    The GIL is released while coding: separate takes can be compressed from several threads.
    Ctrl-C (a pending signal's handler raising) stops the coding after the window at hand and
    raises KeyboardInterrupt. Raises capz.Error (invalid-parameter for an impossible target or
    bad arrays).
    """
    _check_take(take)
    _check_positions(take)
    data, report = _capz.compress(
        take,
        *_coding(max_error, lossless, kg_error, units, codec, clusters, window, check,
                 codec_options, threads, attr_error, drop_fields, analog_max_error,
                 point_order),
        progress,
    )
    return (data, report) if stats else data


def decompress(
    data: Union[bytes, bytearray, memoryview],
    name: str = "",
    *,
    memory_limit: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Take:
    """Decodes .capz bytes back to a Take (`name` is only used in error messages).

    Damaged bytes raise capz.Error (corrupt, not-our-format or unsupported-version); a stream
    asking for more than memory_limit bytes of samples (as in read()) raises "memory-limit".
    progress and Ctrl-C as in read().
    """
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise _invalid(f"decompress wants bytes, got {type(data).__name__}")
    return _capz.decompress(data, name, _memory_limit(memory_limit), progress)


def compress_file(
    input: PathLike,
    output: Optional[PathLike] = None,
    *,
    max_error: Optional[Length] = None,
    lossless: bool = False,
    kg_error: Optional[float] = None,
    codec: str = "none",
    codec_options: Optional[Mapping[str, Any]] = None,
    clusters: int = 0,
    window: int = 0,
    check: bool = True,
    units: Optional[str] = None,
    overwrite: bool = False,
    threads: int = 1,
    attr_error: Optional[Mapping[str, float]] = None,
    drop_fields: bool = False,
    analog_max_error: Optional[Mapping[str, float]] = None,
    point_order: str = "kept",
    progress: Optional[Callable[[int, int], Any]] = None,
    bin_fields: Optional[str] = None,
) -> Dict[str, Any]:
    """Compresses a .c3d, a .trc, a .pcd / .ply / .bin frame or a folder of them to a .capz file:
    the same bytes as `capz compress INPUT -o OUTPUT` with the same options (see compress() for
    them; overwrite is the CLI's -f; bin_fields as read()'s, the CLI's --bin-fields). output defaults to INPUT.capz. The input is read a window
    at a time (and for a C3D or TRC the original file's checksum and residue are stored, and
    with lossless=True those of every PCD, PLY or .bin frame file, so a lossless archive
    rebuilds the files byte for byte). Returns the report as a dict. The CLI's notes are
    UserWarnings (a default bound set without far points; C3D samples marked absent that hold
    coordinates, not kept at a bound; an analog_max_error key that names no channel). progress and Ctrl-C as in compress(): a coding stopped so
    leaves no output file and no temporary behind.
    """
    src = _path(input, "input")
    out = _path(output, "output") if output is not None else src.rstrip("/") + ".capz"
    return _capz.compress_file(
        src,
        out,
        *_coding(max_error, lossless, kg_error, units, codec, clusters, window, check,
                 codec_options, threads, attr_error, drop_fields, analog_max_error,
                 point_order),
        bool(overwrite),
        progress,
        bin_fields or "",
    )


class CapzFile:
    """A .capz opened for random access: its bytes are read once, and frames are decoded on
    demand, only the windows they touch.

        with capz.open("walk.capz") as z:
            part = z.read_frames(first=100, count=50)
            z.info        # what `capz info --json` prints, as a dict
    """

    def __init__(self, path: PathLike, *, memory_limit: Optional[int] = None) -> None:
        self._file: Optional[Any] = _capz.CapzFile(
            _path(path, "path"), _memory_limit(memory_limit)
        )

    def _open(self) -> Any:
        if self._file is None:
            raise Error("usage", "the .capz file is closed", 1)
        return self._file

    def read_frames(self, first: int = 0, count: Optional[int] = None) -> Take:
        """Frames [first, first + count) as a Take (clipped to the take; count None: to the
        end). Only the windows those frames touch are decoded."""
        if first < 0 or (count is not None and count < 0):
            raise _invalid("first and count must be >= 0")
        return self._open().read_frames(int(first), None if count is None else int(count))

    @property
    def info(self) -> Dict[str, Any]:
        """The stream's header, metadata and chunk sizes: the members of `capz info --json`."""
        return self._open().info

    @property
    def frames(self) -> int:
        return self._open().frames

    @property
    def points(self) -> int:
        return self._open().points

    def close(self) -> None:
        self._file = None

    def __enter__(self) -> "CapzFile":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


def open(  # noqa: A001 (capz.open, like gzip.open)
    path: PathLike, *, memory_limit: Optional[int] = None
) -> CapzFile:
    """Opens a .capz for random access (see CapzFile); use it in a with statement.
    memory_limit bounds each read_frames() call as in read()."""
    return CapzFile(path, memory_limit=memory_limit)


def compare(original: Take, reconstruction: Take) -> Dict[str, Any]:
    """Error measures of `reconstruction` against `original` over the original's valid
    samples: max_error_per_coordinate, max_error_euclidean, rmse, kg_error_percent, psnr_db,
    samples, mask_mismatches (samples whose validity differs)."""
    _check_take(original)
    _check_take(reconstruction)
    return _capz.compare(original, reconstruction)
