"""Read mfcd HDF5 output files (layout: doc/output.md).

mfcd writes Fortran arrays, so an array that is (ndim, n) in the code is (n, ndim) here;
strings are fixed-length bytes and real attributes are 1-element arrays. This module
hides both: attributes come back as str / float / int / numpy arrays, particle positions
as (np, ndim), boundary polylines as 0-based index arrays, and a detection grid reshaped
to (ny, nx) (2D) or (nz, ny, nx) (3D) with its axes.

    from mfcd_h5 import MfcdFile
    with MfcdFile("output/example_2_2.h5") as f:
        body = f.body()                 # the detected body (or f.body("block"))
        grid = f.query("grid")          # None when the deck asked for no grid
        print(f.detection["plateau"], grid.det2d.shape)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Optional

import h5py
import numpy as np

__all__ = ["decode", "decode_attrs", "Body", "QuerySet", "MfcdFile", "open_run"]

QUERY_KINDS = ("line", "grid", "points")


def decode(value):
    """An HDF5 attribute value as plain Python: bytes -> str, 1-element arrays -> scalar."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", errors="replace").rstrip("\x00 ")
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "S":
            out = np.char.decode(value, "utf-8")
            return out.item() if out.size == 1 else out
        if value.size == 1:
            return value.reshape(()).item()
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def decode_attrs(obj) -> Dict[str, object]:
    """All attributes of an HDF5 group or dataset, decoded."""
    return {k: decode(v) for k, v in obj.attrs.items()}


@dataclass
class Body:
    """One body's reference particles (/bodies/<name>)."""

    name: str
    x: np.ndarray            #: positions (np, ndim) [m]
    volume: np.ndarray       #: particle volume (np,) [m, m^2 or m^3]
    support: np.ndarray      #: support radius per direction (np, ndim) [m]
    boundary: np.ndarray     #: True for boundary particles (np,)
    loops: List[np.ndarray]  #: boundary polylines, 0-based particle indices, closed loops
    attrs: Dict[str, object] = field(default_factory=dict)

    @property
    def ndim(self) -> int:
        return self.x.shape[1]

    @property
    def np(self) -> int:
        return self.x.shape[0]

    def polylines(self, close: bool = True) -> List[np.ndarray]:
        """Boundary polylines as coordinate arrays (k, ndim); closed ones repeat the start.

        Every loop mfcd generates (polygon, rectangle, annulus) and every loop of a
        particle file is closed, so close=True is right for all current output.
        """
        out = []
        for idx in self.loops:
            if idx.size == 0:
                continue
            if close and idx.size > 2:
                idx = np.append(idx, idx[0])
            out.append(self.x[idx])
        return out


@dataclass
class QuerySet:
    """One detection query set (/detection/line, /detection/grid or /detection/points)."""

    kind: str
    x: np.ndarray                    #: query points (n, ndim) [m]
    det: np.ndarray                  #: det(M) (n,) [-]
    inside: np.ndarray               #: True where det(M) > threshold (n,)
    distance: Optional[np.ndarray]   #: signed distance to the exact boundary (n,) [m], <0 inside
    attrs: Dict[str, object] = field(default_factory=dict)
    s: Optional[np.ndarray] = None   #: line only: arc length from line_from (n,) [m]
    axes: List[np.ndarray] = field(default_factory=list)  #: grid only: axis1, axis2, ... [m]

    @property
    def n(self) -> int:
        return self.det.shape[0]

    @property
    def grid_shape(self):
        """(ny, nx) in 2D, (nz, ny, nx) in 3D, (nx,) in 1D: x runs fastest in the file."""
        return tuple(a.size for a in reversed(self.axes))

    def as_grid(self, values: np.ndarray) -> np.ndarray:
        """Reshape a per-point array of a grid query set to grid_shape (C order, x last)."""
        if self.kind != "grid":
            raise ValueError("as_grid applies to the grid query set only")
        return np.asarray(values).reshape(self.grid_shape)

    @property
    def det2d(self) -> np.ndarray:
        return self.as_grid(self.det)

    @property
    def inside2d(self) -> np.ndarray:
        return self.as_grid(self.inside)

    @property
    def distance2d(self) -> Optional[np.ndarray]:
        return None if self.distance is None else self.as_grid(self.distance)

    def mesh(self):
        """np.meshgrid of the grid axes with indexing 'xy': arrays of grid_shape (2D)."""
        return np.meshgrid(*self.axes, indexing="xy")


class MfcdFile:
    """An mfcd output file opened read-only; use as a context manager or call close()."""

    def __init__(self, path: str):
        self.path = str(path)
        self.h5 = h5py.File(self.path, "r")
        self.attrs = decode_attrs(self.h5)
        if self.attrs.get("code") != "mfcd":
            self.h5.close()
            raise ValueError(f"{self.path}: not an mfcd output file (root attribute code)")

    # context manager -------------------------------------------------------------------
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self.h5 is not None:
            self.h5.close()
            self.h5 = None

    # root ------------------------------------------------------------------------------
    @property
    def ndim(self) -> int:
        return int(self.attrs["ndim"])

    @property
    def title(self) -> str:
        return str(self.attrs.get("title", ""))

    @property
    def deck(self) -> str:
        """The deck verbatim (/deck)."""
        return decode(self.h5["deck"][()]) if "deck" in self.h5 else ""

    # bodies ----------------------------------------------------------------------------
    def body_names(self) -> List[str]:
        return list(self.h5["bodies"].keys()) if "bodies" in self.h5 else []

    def body(self, name: Optional[str] = None) -> Body:
        """A body by name; by default the detected body (or the first one)."""
        if name is None:
            name = self.detection.get("body") or self.body_names()[0]
        g = self.h5["bodies"][name]
        nd = self.ndim
        x = np.asarray(g["x"][()], dtype=float).reshape(-1, nd)
        ptr = np.asarray(g["loop_ptr"][()], dtype=int)
        idx = np.asarray(g["loop_idx"][()], dtype=int)
        # 1-based CSR: loop k is loop_idx[loop_ptr[k]-1 : loop_ptr[k+1]-1] (1-based values)
        loops = [idx[ptr[k] - 1:ptr[k + 1] - 1] - 1 for k in range(ptr.size - 1)]
        return Body(
            name=name,
            x=x,
            volume=np.asarray(g["volume"][()], dtype=float),
            support=np.asarray(g["support"][()], dtype=float).reshape(-1, nd),
            boundary=np.asarray(g["boundary"][()]) != 0,
            loops=loops,
            attrs=decode_attrs(g),
        )

    # detection -------------------------------------------------------------------------
    @property
    def detection(self) -> Dict[str, object]:
        """Attributes of /detection (body, plateau, eps_cr, eps_rel, threshold, rho_buffer)."""
        return decode_attrs(self.h5["detection"]) if "detection" in self.h5 else {}

    def query_kinds(self) -> List[str]:
        if "detection" not in self.h5:
            return []
        return [k for k in QUERY_KINDS if k in self.h5["detection"]]

    def query(self, kind: str) -> Optional[QuerySet]:
        """The query set 'line', 'grid' or 'points', or None when the run has none."""
        if kind not in QUERY_KINDS:
            raise ValueError(f"query kind must be one of {QUERY_KINDS}, not {kind!r}")
        if kind not in self.query_kinds():
            return None
        g = self.h5["detection"][kind]
        nd = self.ndim
        q = QuerySet(
            kind=kind,
            x=np.asarray(g["x"][()], dtype=float).reshape(-1, nd),
            det=np.asarray(g["det"][()], dtype=float),
            inside=np.asarray(g["inside"][()]) != 0,
            distance=np.asarray(g["distance"][()], dtype=float) if "distance" in g else None,
            attrs=decode_attrs(g),
        )
        if "s" in g:
            q.s = np.asarray(g["s"][()], dtype=float)
        j = 1
        while f"axis{j}" in g:
            q.axes.append(np.asarray(g[f"axis{j}"][()], dtype=float))
            j += 1
        if kind == "grid" and int(np.prod(q.grid_shape)) != q.n:
            raise ValueError(f"{self.path}: /detection/grid axes {q.grid_shape} do not match "
                             f"{q.n} points")
        return q


def open_run(path: str) -> MfcdFile:
    """Open an mfcd output file (same as MfcdFile(path))."""
    return MfcdFile(path)
