#!/usr/bin/env python3
"""The two routes from a gmsh script to a body give the same body, bit for bit (issue 11,
item 1): `&body shape = 'geo'`, where mfcd meshes the .geo in memory through gmsh's C API
(src/setup/gmsh_mesh_m.f90) and builds the nodes, volumes, boundary loops and median-dual cells
itself (src/body/mesh_cells_m.f90), and `shape = 'file'` on the particle file tools/mesh_body.py
writes from the same .geo and numbers with gmsh's Python API (with --3d for a 3D deck: the
script's volumes as tetrahedra, /mesh/tetrahedra, read back as the same tetrahedral body).

For each deck given (a deck with one shape = 'geo' body, e.g. input/hertz_sphere_fem.nml), in
a temporary directory: the .geo copied where the deck names it; the mesh file made by
tools/mesh_body.py with the deck's geo_names = geo_values as --set NAME=VALUE; the deck run
twice, as it is and with the body turned into shape = 'file' on that mesh file, both cut
at t_end = 2.5 us, past the first contact (the bodies start 10 um from the wall at 5 m/s).
Then, with one thread:

- every dataset of /bodies (x, volume, support, boundary, the boundary loops, FEM triangles)
  and every group attribute but `shape` ('geo' against 'file');
- every dataset of /history (energies, contact force, penetration, time step, ...: the
  lumped masses, SCNI cells and supports all enter them) and of /snapshots;
- the /summary attributes that do not time the run (the wall time and rates differ)

must be equal bit for bit, not to a tolerance. Why that is the right test: gmsh is the same
library behind both APIs and both make the same calls in the same order, so the two meshes
have the same node coordinates (doubles handed over unchanged); the Fortran port keeps the
script's node filtering and numbering, its triangle orientation, loop order and polygon
vertex order, and sums in numpy's order (numpy.add.at over the first, second, third nodes;
centroids as (a + b) + c then / 3), so the volumes and cells are the same doubles; from
there the two bodies take one code path. Any difference, even in the last bit, is a
difference of the routes.

The shape = 'geo' run gets an empty directory as HOME, which must stay empty: gmsh's GUI
toolkit would write ~/.fltk/fltk.org/fltk.prefs when gmsh starts, and mfcd creates no file
outside its output (src/setup/gmsh_mesh_m.f90).

Exit 77 (skipped) when mfcd is built without gmsh or the gmsh Python module is missing
(`bash tools/setup.sh --gmsh` and a rebuild give both).

Usage: check_geo_equivalence.py /path/to/mfcd DECK.nml [DECK.nml ...]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
T_END = "2.5e-6"
# /summary attributes that time the run rather than describe it
TIMING = ("wall_time", "particle_steps_per_second", "point_steps_per_second", "threads")
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "geo_equivalence." + name
          + ("" if cond else ": " + str(detail)[-1500:]), flush=True)


def has_gmsh(mfcd):
    p = subprocess.run([mfcd, "--version"], capture_output=True, text=True)
    return any(line.startswith("gmsh 4") for line in p.stdout.splitlines())


def geo_body(text):
    """(the &body group's text, file, [(name, value text)]) of the deck's shape = 'geo' body."""
    for m in re.finditer(r"(?ims)^&body\b.*?^/", text):
        g = m.group(0)
        if re.search(r"(?im)^\s*shape\s*=\s*'geo'", g):
            path = re.search(r"(?im)^\s*file\s*=\s*'([^']*)'", g).group(1)
            names = re.findall(r"'([^']*)'", re.search(r"(?im)^\s*geo_names\s*=([^!\n]*)",
                                                       g).group(1))
            values = re.search(r"(?im)^\s*geo_values\s*=([^!\n]*)", g).group(1)
            # Fortran's 1.0d-3 is Python's 1.0e-3 (both read to the nearest double)
            values = [v.strip().lower().replace("d", "e") for v in values.split(",")
                      if v.strip()]
            return g, path, list(zip(names, values))
    raise ValueError("no &body with shape = 'geo'")


def datasets(f, group):
    out = {}
    if group in f:
        f[group].visititems(lambda n, o: out.__setitem__(group + "/" + n, o[()])
                            if isinstance(o, h5py.Dataset) else None)
    return out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)


def compare(label, geo_h5, file_h5):
    with h5py.File(geo_h5, "r") as fg, h5py.File(file_h5, "r") as ff:
        for group in ("bodies", "history", "snapshots"):
            dg, df = datasets(fg, group), datasets(ff, group)
            bad = sorted(k for k in set(dg) | set(df)
                         if k not in dg or k not in df or not same(dg[k], df[k]))
            if group == "snapshots" and not dg and not df:
                continue
            check("%s: /%s, %d datasets equal bit for bit" % (label, group, len(dg)),
                  dg and not bad, bad[:10])
            if group == "history":
                # the comparison must reach contact: the forces then depend on the surface
                # polyline, the supports and (FEM) the triangles too
                n = int(np.max(dg.get("history/n_contact", [0])))
                check("%s: the runs reach contact (up to %d contacting points)" % (label, n),
                      n > 0)
        bad = []
        for name in fg["bodies"]:
            ag, af = dict(fg["bodies"][name].attrs), dict(ff["bodies"][name].attrs)
            for k in set(ag) | set(af):
                if k == "shape":
                    continue
                if k not in ag or k not in af or not same(ag[k], af[k]):
                    bad.append(name + ":" + k)
        check("%s: body attributes equal (shape 'geo' and 'file' aside)" % label, not bad, bad)
        sg, sf = dict(fg["summary"].attrs), dict(ff["summary"].attrs)
        keys = sorted(k for k in set(sg) | set(sf) if k not in TIMING)
        bad = [k for k in keys if k not in sg or k not in sf or not same(sg[k], sf[k])]
        check("%s: /summary, %d attributes equal (timings aside; steps %s, KE %.6e J)"
              % (label, len(keys), sg.get("steps"), float(np.ravel(sg["kinetic_energy"])[0])),
              not bad, bad)


def main():
    mfcd = os.path.abspath(sys.argv[1])
    decks = [os.path.abspath(d) for d in sys.argv[2:]]
    if not has_gmsh(mfcd):
        print("geo_equivalence: mfcd is built without gmsh: skipped")
        sys.exit(77)
    try:
        import gmsh  # noqa: F401
    except ImportError:
        print("geo_equivalence: the gmsh Python module is missing (tools/mesh_body.py): "
              "skipped")
        sys.exit(77)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for deck in decks:
        label = os.path.splitext(os.path.basename(deck))[0]
        text = open(deck).read()
        group, geo, numbers = geo_body(text)
        text = re.sub(r"(?m)^(\s*t_end\s*=\s*)[^!\n]*", r"\g<1>" + T_END, text)
        with tempfile.TemporaryDirectory() as tmp:
            os.makedirs(os.path.join(tmp, os.path.dirname(geo)), exist_ok=True)
            shutil.copy(os.path.join(ROOT, geo), os.path.join(tmp, geo))
            mesh = "meshes/body.h5"
            # --trusted: the shipped scripts go through gmsh's own interpreter here, the
            # independent route the reader's model is compared with
            # (a 3D deck's body: the script's volumes as tetrahedra, mesh_body.py --3d)
            dim3 = ["--3d"] if re.search(r"(?im)^\s*ndim\s*=\s*3", text) else []
            p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mesh_body.py"),
                                "--trusted", geo, mesh] + dim3 + ["--set=%s=%s" % nv
                                                                  for nv in numbers],
                               cwd=tmp, capture_output=True, text=True)
            check("%s: tools/mesh_body.py %s %s" % (label, geo, " ".join(
                "--set %s=%s" % nv for nv in numbers)), p.returncode == 0, p.stderr)
            file_group = re.sub(r"(?im)^\s*shape\s*=\s*'geo'", "  shape = 'file'", group)
            file_group = re.sub(r"(?im)^\s*file\s*=\s*'[^']*'", "  file = '%s'" % mesh,
                                file_group)
            file_group = re.sub(r"(?im)^\s*geo_(names|values)\s*=[^\n]*\n", "", file_group)
            outs = {}
            home = os.path.join(tmp, "home")
            os.makedirs(home)
            for route, body in (("geo", group), ("file", file_group)):
                t = text.replace(group, body)
                t = re.sub(r"(?ims)(^&output\b.*?^\s*file\s*=\s*)'[^']*'",
                           r"\g<1>'out/%s.h5'" % route, t)
                with open(os.path.join(tmp, route + ".nml"), "w") as f:
                    f.write(t)
                p = subprocess.run([mfcd, route + ".nml"], cwd=tmp,
                                   env=dict(env, HOME=home) if route == "geo" else env,
                                   capture_output=True, text=True)
                check("%s: shape = '%s' run completes" % (label, route), p.returncode == 0,
                      p.stdout[-600:] + p.stderr[-600:])
                if route == "geo":
                    made = [os.path.relpath(os.path.join(b, f), home)
                            for b, ds, fs in os.walk(home) for f in ds + fs]
                    check("%s: nothing made in HOME" % label, not made, made)
                outs[route] = os.path.join(tmp, "out", route + ".h5")
            if all(os.path.exists(o) for o in outs.values()):
                compare(label, outs["geo"], outs["file"])
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    sys.exit(0 if results and all(results) else 1)


if __name__ == "__main__":
    main()
