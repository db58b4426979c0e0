"""Read mfcd HDF5 output files (layout: doc/output.md).

This is the one reader of mfcd output: every script in post/ and every regression check
(tests/regression/check_*.py) reads /history, /summary, /bodies, /snapshots, /detection,
/deck and the root attributes through it, so a change of the layout is made here once.
Only what is not an output file's content is read with h5py directly: particle and
checkpoint files (mfcd's inputs), the bit-for-bit comparisons that walk every dataset of
two files, and checks of the raw layout itself (units on every dataset, XDMF references).

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

A dynamic run (snapshots, history, summary; the deck text parsed by parse_deck):

    with MfcdFile("output/elastic_wave.h5") as f:
        snap = f.snapshot(f.snapshot_labels()[-1])   # Snapshot: time (s), step, bodies
        bar = snap.bodies["bar"]                     # SnapshotBody: x, u, v (np, 2), ...
        svm = field_values(bar, "von_mises")         # MPa (units in FIELDS)
        ke = f.history()["ke"]                       # J, or J/m in plane strain
        steel = deck_group(f.deck, "material", name="steel_elastic")   # {variable: value}

A finite-element body (&body discretization = 'fem') also has its triangles and, in each
snapshot, element values:

    with MfcdFile("output/taylor_bar_fem.h5") as f:
        bar = f.body("bar")                          # bar.is_fem, bar.triangles (ne, 3) 0-based
        s = f.snapshot("0005").bodies["bar"]         # s.epsbar_cells (ne,), s.stress_cells (ne, 4)
        e = cell_field_values(s, "epsbar")           # per element, units as FIELDS
        outline = bar.polylines(x=s.x)[0]            # deformed boundary (k, 2)

A body in self-contact (&contact master = slave) has det_self in each snapshot:

    with MfcdFile("output/ring_crush.h5") as f:
        name = f.self_contact_bodies()[0]            # 'ring'
        s = f.snapshot(f.snapshot_labels()[-1]).bodies[name]
        met = s.det_self > s.det_self_threshold      # particles another face covers

A contact run has each particle's mean contact force in each snapshot, and with
&output det_fields = .true. det(M) around each contact pair (the paper's Figs. 9-10):

    with MfcdFile("output/taylor_bar_rkpm.h5") as f:
        s = f.snapshot("0002")
        fc = s.bodies["bar"].f_contact               # (np, 2) N/m, or N in axisymmetry
        d = s.det[1]                                 # DetField of &contact group 1
        plt.contour(d.axis1, d.axis2, d.slave, levels=[d.threshold])
        print(f.snapshot_time("0002"), f.snapshot_body_names("0002"))   # no arrays read

Root attributes are in f.attrs (decoded); a run continued with --restart has f.restart:

    with MfcdFile("out/run.h5") as f:
        print(f.attrs["code_version"], f.restart.get("restart_step"))
"""

from __future__ import annotations

import os
import re
import sys
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import h5py
import numpy as np

__all__ = ["decode", "decode_attrs", "Body", "QuerySet", "MfcdFile", "open_run",
           "SnapshotBody", "Snapshot", "parse_deck", "deck_group", "deck_default", "deck_vars",
           "read_deck_vars", "FIELDS", "field_values",
           "CELL_FIELDS", "cell_field_values", "is_timing", "TIMING_VALUES", "DetField"]

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
    #: finite-element bodies only: triangles (ne, 3), 0-based node indices (rows of x),
    #: counter-clockwise; None for particle bodies
    triangles: Optional[np.ndarray] = None
    #: 3D bodies: the closed boundary surface (nf, 3), 0-based particle indices (rows of
    #: x), counter-clockwise seen from outside; None in 1D and 2D
    facets: Optional[np.ndarray] = None

    @property
    def ndim(self) -> int:
        return self.x.shape[1]

    @property
    def np(self) -> int:
        return self.x.shape[0]

    @property
    def spacing(self) -> Optional[np.ndarray]:
        """The particle spacing per direction (ndim,) [m] (attribute spacing), always an
        array, also in 1D; None when the body has none."""
        sp = self.attrs.get("spacing")
        return None if sp is None else np.atleast_1d(np.asarray(sp, dtype=float))

    @property
    def discretization(self) -> str:
        """'fem' for a finite-element (CST4) body, 'rkpm' for a particle body."""
        return str(self.attrs.get("discretization", "rkpm")).strip().lower()

    @property
    def is_fem(self) -> bool:
        return self.triangles is not None

    @property
    def ne(self) -> int:
        """Number of elements (0 for a particle body)."""
        return 0 if self.triangles is None else self.triangles.shape[0]

    def polylines(self, close: bool = True, x: Optional[np.ndarray] = None) -> List[np.ndarray]:
        """Boundary polylines as coordinate arrays (k, ndim); closed ones repeat the start.

        Every loop mfcd generates (polygon, rectangle, annulus) and every loop of a
        particle file is closed, so close=True is right for all current output. x: other
        positions of the same particles or nodes, e.g. a snapshot's physical positions
        (np, ndim), to get the deformed outline; default the reference positions.
        """
        pos = self.x if x is None else np.asarray(x)
        out = []
        for idx in self.loops:
            if idx.size == 0:
                continue
            if close and idx.size > 2:
                idx = np.append(idx, idx[0])
            out.append(pos[idx])
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


@dataclass
class SnapshotBody:
    """One body in one snapshot of a dynamic run (/snapshots/<label>/<body>)."""

    name: str
    x: np.ndarray                       #: physical particle positions (np, ndim) [m]
    u: Optional[np.ndarray] = None      #: displacements (np, ndim) [m]
    v: Optional[np.ndarray] = None      #: velocities (np, ndim) [m/s]
    stress: Optional[np.ndarray] = None  #: Cauchy stress 11, 22, 33, 12 (np, 4) [Pa]
    epsbar: Optional[np.ndarray] = None  #: effective plastic strain (np,) [-]
    J: Optional[np.ndarray] = None      #: volume ratio det F (np,) [-]
    #: finite-element bodies only: the element values (ne, 4) / (ne,), rows as triangles
    stress_cells: Optional[np.ndarray] = None  #: Cauchy stress 11, 22, 33, 12 [Pa]
    epsbar_cells: Optional[np.ndarray] = None  #: effective plastic strain [-]
    J_cells: Optional[np.ndarray] = None       #: det F [-]
    #: self-contact bodies only (&contact master = slave): det(M) at each particle from the
    #: particles that are not its reference neighbours (np,) [-], and the threshold
    det_self: Optional[np.ndarray] = None
    det_self_threshold: Optional[float] = None
    #: mean contact force on each particle since the previous snapshot (np, 2) [N/m in plane
    #: strain, N in axisymmetry]; zero in the first snapshot (doc/output.md)
    f_contact: Optional[np.ndarray] = None

    @property
    def np(self) -> int:
        return self.x.shape[0]

    @property
    def ne(self) -> int:
        """Number of elements with cell values (0 for a particle body)."""
        for a in (self.epsbar_cells, self.J_cells, self.stress_cells):
            if a is not None:
                return a.shape[0]
        return 0


@dataclass
class DetField:
    """det(M) around one contact pair at one snapshot (/snapshots/<label>/det/contact<k>,
    written with &output det_fields = .true.): the paper's Figs. 9-10."""

    contact: int                     #: k, the &contact group (1-based, deck order)
    axis1: np.ndarray                #: grid coordinates along x1 (r) (nx,) [m]
    axis2: np.ndarray                #: grid coordinates along x2 (z) (ny,) [m]
    master: np.ndarray               #: det(M) of the master on the grid (ny, nx) [-]
    slave: np.ndarray                #: det(M) of the slave (current positions) (ny, nx) [-]
    master_at_slave: np.ndarray      #: det(M_master) at the slave's particles (np_slave,) [-]
    threshold: float                 #: the pair's detection threshold [-]
    master_plateau: float            #: the master's interior plateau of det(M) [-]


@dataclass
class Snapshot:
    """One snapshot (/snapshots/<label>): its time, step, bodies and det(M) fields."""

    label: str
    time: float                         #: [s]
    step: int
    bodies: Dict[str, SnapshotBody] = field(default_factory=dict)
    #: det(M) fields by contact pair k (&output det_fields = .true.); {} without them
    det: Dict[int, DetField] = field(default_factory=dict)
    #: the rigid bodies that move (a ram: &body velocity of a rigid body), where the snapshot
    #: has them: x, u, v only; {} when none moves (the fixed ones are only in /bodies)
    rigid: Dict[str, SnapshotBody] = field(default_factory=dict)


#: Fields that plot_snapshots.py can colour by: name -> (label, unit, scale to the unit).
FIELDS = {
    "epsbar": ("effective plastic strain", "-", 1.0),
    "J": ("J = det F", "-", 1.0),
    "stress_11": ("Cauchy stress 11", "MPa", 1e-6),
    "stress_22": ("Cauchy stress 22", "MPa", 1e-6),
    "stress_33": ("Cauchy stress 33", "MPa", 1e-6),
    "stress_12": ("Cauchy stress 12", "MPa", 1e-6),
    "von_mises": ("von Mises stress", "MPa", 1e-6),
    "v_mag": ("speed |v|", "m/s", 1.0),
    "u_mag": ("displacement |u|", "mm", 1e3),
}


def field_values(b: SnapshotBody, name: str) -> Optional[np.ndarray]:
    """A per-particle field of a snapshot body in the unit of FIELDS[name] (None if absent).

    stress_11 .. stress_12 are the stored components (in axisymmetry 11 = rr, 22 = zz,
    33 = hoop); von_mises = sqrt(3/2 s:s) of the 3D stress (13 = 23 = 0).
    """
    if name not in FIELDS:
        raise ValueError(f"unknown field {name!r}; use one of {', '.join(FIELDS)}")
    scale = FIELDS[name][2]
    if name in ("epsbar", "J"):
        a = getattr(b, name)
        return None if a is None else a * scale
    if name.startswith("stress_") or name == "von_mises":
        if b.stress is None:
            return None
        s = b.stress
        if name == "von_mises":
            p = (s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
            d = s[:, :3] - p[:, None]
            vm = np.sqrt(1.5 * ((d ** 2).sum(axis=1) + 2.0 * s[:, 3] ** 2))
            return vm * scale
        k = {"stress_11": 0, "stress_22": 1, "stress_33": 2, "stress_12": 3}[name]
        return s[:, k] * scale
    a = b.v if name == "v_mag" else b.u
    return None if a is None else np.hypot(a[:, 0], a[:, 1]) * scale


#: Fields with element values in a finite-element snapshot (the *_cells datasets).
CELL_FIELDS = ("epsbar", "J", "stress_11", "stress_22", "stress_33", "stress_12", "von_mises")


def cell_field_values(b: SnapshotBody, name: str) -> Optional[np.ndarray]:
    """A per-element field (ne,) of a finite-element snapshot body, from its epsbar_cells,
    J_cells or stress_cells, in the unit of FIELDS[name]; None when the body has none (a
    particle body) or the field has no element values (v_mag, u_mag)."""
    if name not in FIELDS:
        raise ValueError(f"unknown field {name!r}; use one of {', '.join(FIELDS)}")
    if name not in CELL_FIELDS:
        return None
    cells = SnapshotBody(name=b.name, x=b.x, stress=b.stress_cells, epsbar=b.epsbar_cells,
                         J=b.J_cells)
    return field_values(cells, name)


# ----------------------------------------------------------------------- deck text
_NUM = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")


def _value(tok: str):
    tok = tok.strip()
    if len(tok) >= 2 and tok[0] == tok[-1] and tok[0] in "'\"":
        return tok[1:-1]
    low = tok.lower()
    if low in (".true.", "t", ".t.", "true"):
        return True
    if low in (".false.", "f", ".f.", "false"):
        return False
    if _NUM.match(tok):
        v = float(re.sub("[dD]", "e", tok))
        return int(v) if re.fullmatch(r"[+-]?\d+", tok) else v
    return tok


def _strip_comment(line: str) -> str:
    q = None
    for i, c in enumerate(line):
        if q:
            if c == q:
                q = None
        elif c in "'\"":
            q = c
        elif c == "!":
            return line[:i]
    return line


# the deck's description (src/setup/deck_vars.tsv): each variable's type, count and default, the
# same file mfcd's namelists and checks are generated from
DECK_VARS_PATH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                              "src", "setup", "deck_vars.tsv")


def _literal(text: str, typ: str):
    """A literal of the description ('0.1', "'tensor'", '.true.', '0, 0') as Python."""
    vals = [_typed(_value(t), typ) for t in re.findall(r"'[^']*'|[^,\s]+", text)]
    return vals[0] if len(vals) == 1 else vals


def read_deck_vars(path: str = DECK_VARS_PATH) -> Dict[tuple, dict]:
    """{(group, name): {type, size, unit, default, valid}} of the deck's description; the
    default is None where the description gives none (unset, derived by the reader)."""
    out: Dict[tuple, dict] = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            group, name, typ, dims, _length, unit, default, valid, _hint = line.split("\t")
            size = 1
            for d in ([] if dims == "-" else dims.split()):
                size *= int(d)
            dflt = None
            if default not in ("unset", "huge", "-huge") and not default.startswith("derived "):
                dflt = _literal(default, typ)
            out[(group, name)] = {"type": typ, "size": size, "unit": unit, "default": dflt,
                                  "valid": valid}
    return out


_DECK_VARS: Optional[Dict[tuple, dict]] = None


def deck_vars() -> Dict[tuple, dict]:
    """The deck's description (read_deck_vars), read once; {} without the source tree."""
    global _DECK_VARS
    if _DECK_VARS is None:
        _DECK_VARS = read_deck_vars() if os.path.exists(DECK_VARS_PATH) else {}
    return _DECK_VARS


def _typed(v, typ: str):
    """v (from _value) as the description's type: int, float, bool or str."""
    if typ == "real" and isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(v)
    if typ == "integer" and isinstance(v, (int, float)) and not isinstance(v, bool):
        return int(v)
    if typ == "string":
        return v if isinstance(v, str) else str(v)
    return v


def parse_deck(text: str) -> List[tuple]:
    """The namelist groups of a deck text, in order: [(group, {variable: value}), ...].

    A small reader for post-processing, not a Fortran namelist parser: names are lower-cased;
    values are typed by the deck's description (src/setup/deck_vars.tsv): reals float, integers
    int, logicals bool, strings str; an array variable (lo, velocity, snapshot_times) is a
    list, a scalar one value. A variable the description does not know keeps the reader's
    guess (one entry a scalar, several a list). A repeat count r*v gives r values.
    """
    desc = deck_vars()
    body = "\n".join(_strip_comment(l) for l in text.splitlines())
    groups = []
    # a group runs from &name to the first '/' outside quotes
    for m in re.finditer(r"&(\w+)((?:'[^']*'|\"[^\"]*\"|[^/'\"])*)/", body):
        name, content = m.group(1).lower(), m.group(2)
        if name == "end":
            continue
        vals: Dict[str, object] = {}
        toks = re.findall(r"'[^']*'|\"[^\"]*\"|=|,|[^\s,=]+", content)
        key, cur = None, []

        def store():
            d = desc.get((name, re.sub(r"\(.*", "", key)))
            if d is None:
                vals[key] = cur[0] if len(cur) == 1 else cur
                return
            typed = [_typed(v, d["type"]) for v in cur]
            vals[key] = typed if d["size"] > 1 and "(" not in key else \
                (typed[0] if len(typed) == 1 else typed)

        for i, t in enumerate(toks):
            if t not in ("=", ",") and i + 1 < len(toks) and toks[i + 1] == "=" \
                    and re.match(r"[A-Za-z]\w*(\(.*\))?$", t):
                if key is not None:
                    store()
                key, cur = t.lower(), []
            elif t not in ("=", ","):
                rep = re.fullmatch(r"(\d+)\*(.+)", t) if t[0] not in "'\"" else None
                if rep:
                    cur.extend([_value(rep.group(2))] * int(rep.group(1)))
                else:
                    cur.append(_value(t))
        if key is not None:
            store()
        groups.append((name, vals))
    return groups


def negative_values(argv: Optional[List[str]] = None) -> List[str]:
    """argv (default sys.argv[1:]) with each option's value that begins with '-' and a
    digit or '.' joined to it ('--window', '-0.006,0.006' -> '--window=-0.006,0.006'):
    argparse takes a comma list of numbers that begins with a minus for an option and
    refuses it (it accepts a lone negative number only)."""
    args = list(sys.argv[1:] if argv is None else argv)
    out: List[str] = []
    i = 0
    while i < len(args):
        a = args[i]
        if (a.startswith("--") and "=" not in a and i + 1 < len(args)
                and re.match(r"-[0-9.]", args[i + 1])):
            out.append(a + "=" + args[i + 1])
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def deck_default(group: str, name: str):
    """The default of variable name of &group from the deck's description (None where the
    reader derives it or the description is not at hand)."""
    d = deck_vars().get((group.lower(), name.lower()))
    return None if d is None else d["default"]


def deck_group(text: str, group: str, **match) -> Optional[Dict[str, object]]:
    """The first group named `group` whose variables equal `match` (e.g. name='steel')."""
    for g, vals in parse_deck(text):
        if g == group.lower() and all(vals.get(k) == v for k, v in match.items()):
            return vals
    return None


class MfcdFile:
    """An mfcd output file opened read-only; use as a context manager or call close().

    attrs: the root attributes decoded (code, code_version, git_commit, created, deck_path,
    title, mode, geometry, ndim, units and, after --restart, those of `restart`).
    """

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
        """The deck verbatim (/deck): stored at its exact length, so nothing is stripped
        (a deck that ends in blanks keeps them)."""
        if "deck" not in self.h5:
            return ""
        v = self.h5["deck"][()]
        return v.decode("utf-8", errors="replace") if isinstance(v, bytes) else str(v)

    @property
    def restart(self) -> Dict[str, object]:
        """The root attributes of a run continued with --restart (restarted_from,
        restart_step, restart_time, snapshots_before_restart; doc/output.md), {} for a
        run from t = 0. Every root attribute is in self.attrs."""
        keys = ("restarted_from", "restart_step", "restart_time", "snapshots_before_restart")
        return {k: self.attrs[k] for k in keys if k in self.attrs}

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
        tri = np.asarray(g["triangles"][()], dtype=int).reshape(-1, 3) \
            if "triangles" in g else None
        fac = np.asarray(g["facets"][()], dtype=int).reshape(-1, 3) \
            if "facets" in g else None
        return Body(
            name=name,
            x=x,
            volume=np.asarray(g["volume"][()], dtype=float),
            support=np.asarray(g["support"][()], dtype=float).reshape(-1, nd),
            boundary=np.asarray(g["boundary"][()]) != 0,
            loops=loops,
            attrs=decode_attrs(g),
            triangles=tri,
            facets=fac,
        )

    def triangles(self, name: str) -> Optional[np.ndarray]:
        """/bodies/<name>/triangles (ne, 3), 0-based node indices; None for a particle body."""
        g = self.h5["bodies"][name]
        return np.asarray(g["triangles"][()], dtype=int).reshape(-1, 3) \
            if "triangles" in g else None

    def is_rigid(self, name: str) -> bool:
        """Whether body `name` is rigid (the group attribute role; from the deck when the
        file predates it)."""
        role = self.h5["bodies"][name].attrs.get("role")
        if role is None:
            spec = deck_group(self.deck, "body", name=name) or {}
            role = spec.get("role", "deformable")
        return str(decode(role)).strip().lower() == "rigid"

    def discretization(self, name: str) -> str:
        """'fem' or 'rkpm' (the group attribute; 'rkpm' when the file predates it)."""
        g = self.h5["bodies"][name]
        return str(decode(g.attrs.get("discretization", b"rkpm"))).strip().lower()

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


    # dynamic runs -----------------------------------------------------------------------
    @property
    def geometry(self) -> str:
        return str(self.attrs.get("geometry", "plane"))

    @property
    def mode(self) -> str:
        return str(self.attrs.get("mode", "detect"))

    def snapshot_labels(self) -> List[str]:
        """Snapshot labels in time order ('0001', '0002', ..., then 'failure' if written)."""
        if "snapshots" not in self.h5:
            return []
        labs = list(self.h5["snapshots"].keys())
        return sorted(labs, key=self.snapshot_time)

    def snapshot_time(self, label: str) -> float:
        """The time of snapshot `label` (s), without reading its arrays."""
        return float(decode(self.h5["snapshots"][label].attrs["time"]))

    def snapshot_body_names(self, label: str) -> List[str]:
        """The deformable bodies in snapshot `label` (groups with x that are not a moving
        rigid body's), without reading their arrays."""
        g = self.h5["snapshots"][label]
        return [n for n in g.keys() if isinstance(g[n], h5py.Group) and "x" in g[n]
                and not (n in self.body_names() and self.is_rigid(n))]

    def snapshot(self, label: str) -> Snapshot:
        """/snapshots/<label> with every body in it, arrays as (np, ndim) / (np, ncomp) /
        (np,) (ndim 2: the stress's 4 components 11, 22, 33, 12; ndim 3: its 6, 11, 22, 33,
        23, 13, 12), and its det(M) fields (Snapshot.det) if the run wrote them."""
        g = self.h5["snapshots"][label]
        nd = self.ndim
        nc = 6 if nd == 3 else 4
        snap = Snapshot(label=label, time=float(decode(g.attrs["time"])),
                        step=int(decode(g.attrs.get("step", -1))))
        for name in g.keys():
            gb = g[name]
            if not isinstance(gb, h5py.Group) or "x" not in gb:
                continue

            def arr(key, cols=None):
                if key not in gb:
                    return None
                a = np.asarray(gb[key][()], dtype=float)
                return a.reshape(-1, cols) if cols else a

            if name in self.body_names() and self.is_rigid(name):
                snap.rigid[name] = SnapshotBody(name=name, x=arr("x", nd), u=arr("u", nd),
                                                v=arr("v", nd))
                continue
            snap.bodies[name] = SnapshotBody(
                name=name, x=arr("x", nd), u=arr("u", nd), v=arr("v", nd),
                stress=arr("stress", nc), epsbar=arr("epsbar"), J=arr("J"),
                stress_cells=arr("stress_cells", nc), epsbar_cells=arr("epsbar_cells"),
                J_cells=arr("J_cells"), det_self=arr("det_self"),
                det_self_threshold=float(decode(gb.attrs["det_self_threshold"]))
                if "det_self_threshold" in gb.attrs else None,
                f_contact=arr("f_contact", nd))
        if "det" in g:
            for name, gd in g["det"].items():
                if not name.startswith("contact"):
                    continue
                k = int(name[len("contact"):])
                snap.det[k] = DetField(
                    contact=k,
                    axis1=np.asarray(gd["axis1"][()], dtype=float),
                    axis2=np.asarray(gd["axis2"][()], dtype=float),
                    master=np.asarray(gd["master"][()], dtype=float),
                    slave=np.asarray(gd["slave"][()], dtype=float),
                    master_at_slave=np.asarray(gd["master_at_slave"][()], dtype=float),
                    threshold=float(decode(gd.attrs["threshold"])),
                    master_plateau=float(decode(gd.attrs["master_plateau"])))
            snap.det = dict(sorted(snap.det.items()))
        return snap

    def self_contact_bodies(self, label: Optional[str] = None) -> List[str]:
        """Names of the bodies of self-contact pairs (&contact master = slave): those with a
        det_self dataset in snapshot `label` (default the first snapshot), without reading
        any array; [] when the run has no snapshots or no self-contact."""
        labels = self.snapshot_labels()
        if not labels:
            return []
        g = self.h5["snapshots"][label or labels[0]]
        return [n for n in g.keys() if isinstance(g[n], h5py.Group) and "det_self" in g[n]]

    def materials(self) -> Dict[str, Dict[str, object]]:
        """/materials/<name>: {name: {'model', 'preset', each constant the model uses (SI),
        '<constant>_source' ('given', 'preset' or 'default')}}; {} for files written before
        mfcd kept them."""
        g = self.h5.get("materials")
        if g is None:
            return {}
        return {n: decode_attrs(g[n]) for n in g}

    def _history_datasets(self) -> Dict[str, "h5py.Dataset"]:
        """Every /history dataset by its path below /history: the run's columns ('ke',
        ...) and each deformable body's ('bodies/<name>/ke', ...)."""
        if "history" not in self.h5:
            return {}
        out: Dict[str, h5py.Dataset] = {}
        self.h5["history"].visititems(
            lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
        return out

    def history(self) -> Dict[str, np.ndarray]:
        """/history columns as arrays (time in s, energies in J or J/m), the bodies' as
        'bodies/<name>/<column>' (body_history); {} if none."""
        return {k: np.asarray(v[()]) for k, v in self._history_datasets().items()}

    def body_history(self, body: str) -> Dict[str, np.ndarray]:
        """/history/bodies/<body>: the body's kinetic energy 'ke', momentum ('momentum_x',
        'momentum_y'; axisymmetry 'momentum_z') and, in plane strain, 'angular_momentum'
        about its centre of mass, one value per history row; {} if the file has none."""
        h = self.h5.get("history/bodies/" + body)
        if h is None:
            return {}
        return {k: np.asarray(v[()]) for k, v in h.items()}

    def history_units(self) -> Dict[str, str]:
        """{column: unit} of the /history columns that carry a units attribute (all of
        them in mfcd's output; a column without one is left out)."""
        return {k: str(decode(v.attrs["units"])) for k, v in self._history_datasets().items()
                if "units" in v.attrs}

    @property
    def summary(self) -> Dict[str, object]:
        """The run's values in /summary (status, steps, time, energy_residual, ...), numbers
        as float / int, strings as str; {} before the run has ended. Units:
        summary_units()."""
        return self._summary_group("summary")[0]

    def summary_units(self, group: str = "") -> Dict[str, str]:
        """The unit of each number in /summary (group ''), or in one of its groups
        ('timing', 'bodies/<name>', 'contacts/contact<k>'): {name: unit}."""
        return self._summary_group("summary/" + group if group else "summary")[1]

    @property
    def summary_timing(self) -> Dict[str, float]:
        """/summary/timing: wall time of the time loop and of its parts (s): time_loop,
        kinematics, material, internal_force, contact, snapshots."""
        return self._summary_group("summary/timing")[0]

    def summary_bodies(self) -> Dict[str, Dict[str, object]]:
        """/summary/bodies: per deformable body at the end of the run, {name: {length,
        width, foot_radius (m), max_epsbar, quiet_point_steps_skipped}}."""
        if "summary/bodies" not in self.h5:
            return {}
        return {n: self._summary_group("summary/bodies/" + n)[0]
                for n in self.h5["summary/bodies"].keys()}

    def summary_contacts(self) -> Dict[int, Dict[str, object]]:
        """/summary/contacts: per &contact group k (1-based, deck order), {k: {master,
        slave, detector, self, screened, evaluated, detected, contacts, skipped_far,
        detect_time, pair_time, ...}} (doc/output.md lists them with their units)."""
        if "summary/contacts" not in self.h5:
            return {}
        out = {}
        for n in self.h5["summary/contacts"].keys():
            out[int(n[len("contact"):])] = self._summary_group("summary/contacts/" + n)[0]
        return dict(sorted(out.items()))

    def summary_flat(self) -> Dict[str, object]:
        """Every value of /summary keyed by its path below /summary: 'steps',
        'timing/contact', 'bodies/bar/length', 'contacts/contact1/screened', ... (to
        compare two runs value by value; is_timing() tells the wall-clock ones)."""
        out = dict(self.summary)
        if "summary" not in self.h5:
            return out
        groups = []
        self.h5["summary"].visit(lambda k: groups.append(k)
                                 if isinstance(self.h5["summary"][k], h5py.Group) else None)
        for g in groups:
            for k, v in self._summary_group("summary/" + g)[0].items():
                out[g + "/" + k] = v
        return out

    def self_contact_pair(self) -> Optional[int]:
        """The number k of the run's self-contact pair (master = slave), None if it has
        none (the first, if it has several)."""
        for k, c in self.summary_contacts().items():
            if int(c.get("self", 0)) == 1:
                return k
        return None

    def _summary_group(self, path: str):
        """(values, units) of a /summary group: its attributes decoded, 1-element numbers
        as scalars, the 'units' attribute parsed into {name: unit}."""
        if path not in self.h5:
            return {}, {}
        vals = {}
        units: Dict[str, str] = {}
        for k, v in decode_attrs(self.h5[path]).items():
            if k == "units":
                for item in str(v).split(";"):
                    if "=" in item:
                        name, unit = item.split("=", 1)
                        units[name.strip()] = unit.strip()
                continue
            if isinstance(v, np.ndarray) and v.size == 1:
                v = v.reshape(()).item()
            vals[k] = v
        return vals, units

    def deck_groups(self) -> List[tuple]:
        """The stored deck parsed by parse_deck."""
        return parse_deck(self.deck)


#: /summary values that are wall-clock measurements (they differ between identical runs)
TIMING_VALUES = ("wall_time", "particle_steps_per_second", "point_steps_per_second")


def is_timing(key: str) -> bool:
    """True for a summary_flat() key that is a wall-clock measurement: wall_time, the
    throughputs, everything in /summary/timing, and each contact pair's detect_time and
    pair_time."""
    return (key in TIMING_VALUES or key.startswith("timing/")
            or (key.startswith("contacts/") and key.endswith(("/detect_time", "/pair_time"))))


def open_run(path: str) -> MfcdFile:
    """Open an mfcd output file (same as MfcdFile(path))."""
    return MfcdFile(path)
