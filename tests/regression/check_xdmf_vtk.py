#!/usr/bin/env python3
"""The <stem>.xdmf beside an mfcd output file, read by VTK's own XDMF reader (the `vtk` wheel
from PyPI: vtkXdmfReader of vtkIOXdmf2, or vtkXdmf3Reader of vtkIOXdmf3 where the wheel
has it), checked against the .h5 it points at (input/bar_impact_elastic_fem_coarse.nml, 1 s):

  reading: the reader accepts the file, reports one time step per snapshot at the snapshot
     times, and neither it nor the XDMF library reports an error (VTK error events, the VTK
     output window, and the library's own messages on stderr);
  finite-element bodies (/bodies/<name>/triangles) at the last time step: a block with np
     points (rows of /bodies/<name>/x) at the snapshot's positions x, ne cells (rows of
     triangles), every one VTK_TRIANGLE with the file's 0-based node numbers; the cell array
     epsbar_cells (ne values, equal to the file's) and the point array v (np tuples, equal to
     the file's) exist, and the stress components as scalars (stress_cells_11 .. _12 per
     cell, HyperSlabs of the file's (ne, 4) stress_cells) equal the file's columns;
  every deformable body: the point arrays stress_11, _22, _33, _12 (np values each) equal the
     columns of the file's stress;
  particle bodies: a deformable one (in the snapshots) is a block of np points whose cells are
     vertices over all np points;
  rigid bodies (only in /bodies, not in the snapshots): at the first and at the last time
     step a block named after the body with np points at /bodies/<name>/x (they do not move)
     and, for a particle body, vertex cells over all np points; for a finite-element one,
     its triangles. The deck must have a rigid body.
Then the deck again with its rigid bodies made finite-element bodies (discretization =
'fem' added to each rigid &body group, written to a scratch directory): the rigid blocks
are triangle grids on /bodies/<name>/triangles.
The program must run the deck to completion (exit 0). Without the vtk module the check is
skipped (exit 77, registered with SKIP_RETURN_CODE 77): pip install vtk.
Usage: check_xdmf_vtk.py /path/to/mfcd /path/to/deck.nml
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

SKIP = 77
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "xdmf_vtk." + name
          + ("" if cond else ": " + str(detail)[:2000]))


def info(text):
    print("[ INFO ] xdmf_vtk." + text)


def finish():
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


def load_reader():
    """(module vtk, reader instance, class name) or exit 77 when VTK or its XDMF reader is
    not installed."""
    try:
        import vtk  # noqa: F401  (the whole wheel: also sets up the output window)
    except ImportError as e:
        print(f"xdmf_vtk: SKIPPED: the Python module 'vtk' is not installed in {sys.executable} "
              f"({e}); install it with '{sys.executable} -m pip install vtk' to run this check")
        sys.exit(SKIP)
    for mod, cls in (("vtkmodules.vtkIOXdmf2", "vtkXdmfReader"),
                     ("vtkmodules.vtkIOXdmf3", "vtkXdmf3Reader")):
        try:
            m = __import__(mod, fromlist=[cls])
            return vtk, getattr(m, cls)(), cls
        except (ImportError, AttributeError):
            continue
    print(f"xdmf_vtk: SKIPPED: vtk {vtk.vtkVersion.GetVTKVersion()} has neither "
          "vtkXdmfReader (vtkIOXdmf2) nor vtkXdmf3Reader (vtkIOXdmf3)")
    sys.exit(SKIP)


class Captured:
    """Collects what VTK and the XDMF library report while reading: error and warning events
    of the reader, the VTK output window's text, and everything written to file descriptor 2
    (the XDMF library prints its errors there, past VTK)."""

    def __init__(self, vtk, reader):
        self.vtk, self.events = vtk, []
        self.window = vtk.vtkStringOutputWindow()
        vtk.vtkOutputWindow.SetInstance(self.window)
        for ev in ("ErrorEvent", "WarningEvent"):
            reader.AddObserver(ev, lambda obj, e: self.events.append(e))
        self.stderr_text = ""

    def __enter__(self):
        sys.stderr.flush()
        self.tmp = tempfile.TemporaryFile(mode="w+b")
        self.saved = os.dup(2)
        os.dup2(self.tmp.fileno(), 2)
        return self

    def __exit__(self, *exc):
        sys.stderr.flush()
        os.dup2(self.saved, 2)
        os.close(self.saved)
        self.tmp.seek(0)
        self.stderr_text += self.tmp.read().decode("utf-8", errors="replace")
        self.tmp.close()

    def problems(self):
        text = self.window.GetOutput() or ""
        out = [f"reader {e}" for e in self.events]
        if re.search(r"\b(error|warning)\b", text, re.I):
            out.append("VTK output window: " + text.strip())
        if re.search(r"\b(error|fail|cannot|can't|unable)", self.stderr_text, re.I):
            out.append("stderr: " + self.stderr_text.strip())
        return out


def blocks(vtk, obj, out=None):
    """{name: dataset} of the leaves of a (nested) multiblock; the reader names a block
    '<grid>[<time index>]': the index is dropped."""
    out = {} if out is None else out
    if obj is None:
        return out
    if obj.IsA("vtkMultiBlockDataSet"):
        for i in range(obj.GetNumberOfBlocks()):
            b = obj.GetBlock(i)
            name = ""
            if obj.HasMetaData(i):
                name = obj.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()) or ""
            if b is not None and b.IsA("vtkDataSet"):
                out[re.sub(r"\[\d+\]$", "", name)] = b
            else:
                blocks(vtk, b, out)
    elif obj.IsA("vtkDataSet"):
        out[""] = obj
    return out


def array(data, name):
    a = data.GetArray(name)
    if a is None:
        return None
    from vtkmodules.util.numpy_support import vtk_to_numpy
    v = vtk_to_numpy(a)
    return v.reshape(a.GetNumberOfTuples(), a.GetNumberOfComponents())


def cell_types_and_connectivity(ds):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    n = ds.GetNumberOfCells()
    types = np.array([ds.GetCellType(i) for i in range(n)], dtype=int)
    cells = ds.GetCells() if hasattr(ds, "GetCells") else None
    conn = offs = None
    if cells is not None and hasattr(cells, "GetConnectivityArray"):
        conn = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
        offs = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    return types, conn, offs


def run_deck(mfcd, deck_text, deck_name, tag):
    """Run the deck text in a scratch directory: (h5 path, xdmf path) or None."""
    work = tempfile.mkdtemp(prefix="mfcd_xdmf_vtk_")
    deck = os.path.join(work, deck_name)
    with open(deck, "w") as fh:
        fh.write(deck_text)
    p = subprocess.run([mfcd, deck], cwd=work, capture_output=True, text=True, timeout=1800)
    check(tag + "run exits 0", p.returncode == 0, p.stderr[-2000:])
    if p.returncode:
        return None
    out = [l for l in deck_text.splitlines() if re.match(r"\s*file\s*=", l) and ".h5" in l][0]
    h5path = os.path.join(work, re.search(r"['\"]([^'\"]+)['\"]", out).group(1))
    xdmf = os.path.splitext(h5path)[0] + ".xdmf"
    check(tag + "the .h5 and the .xdmf exist",
          os.path.isfile(h5path) and os.path.isfile(xdmf), (h5path, xdmf))
    if not os.path.isfile(xdmf):
        return None
    return h5path, xdmf


def rigid_as_fem(deck_text):
    """The deck with discretization = 'fem' after the role = 'rigid' line of every rigid
    &body group (such a deck keeps the rigid body's nodes and adds its triangles)."""
    return re.sub(r"^(\s*role\s*=\s*['\"]rigid['\"].*)$", r"\1\n  discretization = 'fem'",
                  deck_text, flags=re.M | re.I)


def check_file(vtk, reader, cls, h5path, xdmf, tag="", need_fem=True):
    f = MfcdFile(h5path)
    labels = f.snapshot_labels()
    snap_t = np.array([f.snapshot_time(k) for k in labels])
    last = labels[-1]
    last_snap = f.snapshot(last)
    bodies = {}
    for name in f.body_names():
        g = f.body(name)
        bodies[name] = dict(np=g.np, disc=g.discretization, x=g.x, tri=g.triangles,
                            deformable=name in last_snap.bodies)
    if need_fem:
        check(tag + "the file has a deformable finite-element body",
              any(b["tri"] is not None and b["deformable"] for b in bodies.values()),
              {n: b["disc"] for n, b in bodies.items()})
    check(tag + "the file has a rigid body (in /bodies, not in the snapshots)",
          any(not b["deformable"] for b in bodies.values()), sorted(bodies))

    cap = Captured(vtk, reader)
    with cap:
        can = reader.CanReadFile(xdmf)
        reader.SetFileName(xdmf)
        reader.Modified()
        reader.UpdateInformation()
    check(tag + f"{cls} can read {os.path.basename(xdmf)}", can, can)
    oi = reader.GetOutputInformation(0)
    sddp = vtk.vtkStreamingDemandDrivenPipeline
    steps = np.array(oi.Get(sddp.TIME_STEPS()) if oi.Has(sddp.TIME_STEPS()) else [])
    check(tag + f"{steps.size} time steps at the {len(labels)} snapshot times",
          steps.size == len(labels) and np.allclose(steps, snap_t, rtol=1e-9, atol=1e-15),
          (steps, snap_t))

    def read_at(t):
        with cap:
            ok = reader.UpdateTimeStep(float(t)) if steps.size else reader.Update()
        probs = cap.problems()
        check(tag + f"the reader reports no error at t = {t:.6g} s",
              ok in (None, 1, True) and not probs,
              f"update returned {ok}; " + " | ".join(probs))
        got = blocks(vtk, reader.GetOutputDataObject(0))
        info(tag + f"blocks at t = {t:.6g} s: "
             + ", ".join(f"{n}: {d.GetNumberOfPoints()} points, {d.GetNumberOfCells()} cells"
                         for n, d in got.items()))
        return got

    first_blocks = read_at(snap_t[0])
    # the rigid bodies' blocks are copied out before the reader runs again
    first_rigid = {}
    for name, b in bodies.items():
        if not b["deformable"] and name in first_blocks:
            d = first_blocks[name].NewInstance()
            d.DeepCopy(first_blocks[name])
            first_rigid[name] = d
    got = read_at(snap_t[-1])
    from vtkmodules.util.numpy_support import vtk_to_numpy

    for name, b in bodies.items():
        npt = b["np"]
        if not b["deformable"]:
            for when, ds in (("first", first_rigid.get(name)), ("last", got.get(name))):
                what = f"{name}: rigid {b['disc']} body at the {when} time step: "
                check(tag + what + "a block", ds is not None,
                      sorted(first_rigid if when == "first" else got))
                if ds is None:
                    continue
                check(tag + what + f"{ds.GetNumberOfPoints()} points = np = {npt}",
                      ds.GetNumberOfPoints() == npt, ds.GetNumberOfPoints())
                pts = vtk_to_numpy(ds.GetPoints().GetData()) if ds.GetPoints() is not None \
                    else None
                nd = b["x"].shape[1]
                check(tag + what + f"points = /bodies/{name}/x",
                      pts is not None and pts.shape[0] == npt
                      and np.array_equal(pts[:, :nd], b["x"]) and np.all(pts[:, nd:] == 0.0),
                      None if pts is None else (pts[:3], b["x"][:3]))
                types, conn, offs = cell_types_and_connectivity(ds)
                if b["tri"] is not None:
                    tri = np.asarray(b["tri"], dtype=np.int64)
                    check(tag + what + f"{types.size} VTK_TRIANGLE cells = /bodies/{name}/"
                          "triangles", types.size == tri.shape[0]
                          and np.all(types == vtk.VTK_TRIANGLE)
                          and (conn is None or np.array_equal(conn.reshape(-1, 3), tri)),
                          (types.size, tri.shape))
                else:
                    vert = (vtk.VTK_VERTEX, vtk.VTK_POLY_VERTEX)
                    covered = np.unique(conn) if conn is not None else None
                    check(tag + what + f"vertex cells over all {npt} points",
                          types.size > 0 and np.all(np.isin(types, vert))
                          and (covered is None or covered.size == npt),
                          (np.unique(types), None if covered is None else covered.size))
            continue
        ds = got.get(name)
        if ds is None:
            check(tag + f"{name}: a block for the deformable body", False, sorted(got))
            continue
        g = last_snap.bodies[name]
        check(tag + f"{name}: {ds.GetNumberOfPoints()} points = np = {npt}",
              ds.GetNumberOfPoints() == npt, ds.GetNumberOfPoints())
        pts = vtk_to_numpy(ds.GetPoints().GetData()) if ds.GetPoints() is not None else None
        check(tag + f"{name}: points at the last snapshot's x",
              pts is not None and pts.shape[0] == npt
              and np.allclose(pts[:, :2], g.x, rtol=0, atol=1e-12)
              and np.all(pts[:, 2:] == 0.0), None if pts is None else pts[:3])
        types, conn, offs = cell_types_and_connectivity(ds)
        v = array(ds.GetPointData(), "v")
        check(tag + f"{name}: point array v with {npt} tuples (the file's v)",
              v is not None and v.shape[0] == npt and np.allclose(v[:, :2], g.v),
              None if v is None else v.shape)
        if b["tri"] is not None:
            tri = np.asarray(b["tri"], dtype=np.int64)
            ne = tri.shape[0]
            check(tag + f"{name}: {types.size} cells = ne = {ne}", types.size == ne, types.size)
            check(tag + f"{name}: every cell VTK_TRIANGLE ({vtk.VTK_TRIANGLE})",
                  types.size > 0 and np.all(types == vtk.VTK_TRIANGLE), np.unique(types))
            if conn is not None:
                check(tag + f"{name}: cell connectivity = /bodies/{name}/triangles (0-based)",
                      conn.size == 3 * ne and np.array_equal(conn.reshape(-1, 3), tri),
                      (conn[:6], tri[:2]))
            e = array(ds.GetCellData(), "epsbar_cells")
            check(tag + f"{name}: cell array epsbar_cells with {ne} values (the file's)",
                  e is not None and e.shape == (ne, 1)
                  and np.allclose(e[:, 0], g.epsbar_cells),
                  None if e is None else e.shape)
            for c, comp in enumerate(("11", "22", "33", "12")):
                sc = array(ds.GetCellData(), "stress_cells_" + comp)
                check(tag + f"{name}: cell array stress_cells_{comp} = column {c} of the "
                      f"file's stress_cells", sc is not None and sc.shape == (ne, 1)
                      and np.allclose(sc[:, 0], g.stress_cells[:, c], rtol=0,
                                      atol=1e-9 * max(1.0, np.abs(g.stress_cells).max())),
                      None if sc is None else sc.shape)
        for c, comp in enumerate(("11", "22", "33", "12")):
            sp = array(ds.GetPointData(), "stress_" + comp)
            check(tag + f"{name}: point array stress_{comp} = column {c} of the file's stress",
                  sp is not None and sp.shape == (npt, 1)
                  and np.allclose(sp[:, 0], g.stress[:, c], rtol=0,
                                  atol=1e-9 * max(1.0, np.abs(g.stress).max())),
                  None if sp is None else sp.shape)
        if b["tri"] is None:
            vert = (vtk.VTK_VERTEX, vtk.VTK_POLY_VERTEX)
            covered = np.unique(conn) if conn is not None else None
            check(tag + f"{name}: particle body: vertex cells over all {npt} points",
                  types.size > 0 and np.all(np.isin(types, vert))
                  and (covered is None or covered.size == npt),
                  (np.unique(types), None if covered is None else covered.size))
    f.close()


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    mfcd, deck = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    vtk, reader, cls = load_reader()
    info(f"vtk {vtk.vtkVersion.GetVTKVersion()}, reader {cls}")
    text = open(deck).read()
    files = run_deck(mfcd, text, os.path.basename(deck), "")
    if files is None:
        finish()
    check_file(vtk, reader, cls, *files)
    # the same deck with its rigid bodies as finite-element meshes: triangle grids
    fem_text = rigid_as_fem(text)
    check("rigid_fem: the deck has a rigid body to make a mesh of", fem_text != text)
    if fem_text != text:
        # a fresh reader: the XDMF readers cache what they read by file name
        _, reader2, _ = load_reader()
        files = run_deck(mfcd, fem_text, "rigid_fem_" + os.path.basename(deck), "rigid_fem: ")
        if files is not None:
            check_file(vtk, reader2, cls, *files, tag="rigid_fem: ", need_fem=False)
    finish()

if __name__ == "__main__":
    main()
