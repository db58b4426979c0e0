#!/usr/bin/env python3
"""A user's plane particle file read per part by mfcd_mpi (src/setup/tri_file_m.f90): each
rank reads its share of the file's nodes and triangles and the region its part needs
(doc/parallel.md, "Plane mesh files read per part"), rank 0 checking the whole body once
and writing the whole file's facts (spacing, longest edge, extent) into a scratch file of
its own, removed after the set-up; the user's file is only read.

The ring of tests/mpi/ring.geo meshed once by tools/mesh_body.py (the gmsh Python module of
.venv; exit 77, skipped, without it), the decks tests/mpi/ring_crush_geo*.nml given that file
(&body shape = 'file', by its triangles and by RKPM over its median-dual cells), then
tests/mpi/check_mpi_run.py on 2 and 3 ranks to 12 us (the ram and the floor in contact, the
self-contact pair set up over the parts; its forces come later, mpi_run_geo_2d_self): every
dataset bit for bit against mfcd, a checkpoint of 2 ranks continued on 3 and by mfcd, each
body read per part (--made: no rank read all its nodes); the user's file the same bytes
after the runs. Then files the serial run refuses, refused on 2 and 4 ranks with its
message, nothing written (--bad-file): a triangle naming a node past the last (the file
carries its triangles, so it would be read per part: rank 0's whole check finds it first),
and an RKPM body's file without its median-dual cells (not read per part: every rank builds
it as mfcd does).

Usage: check_plane_file_mpi.py MFCD MFCD_MPI MPIEXEC
"""
import hashlib
import os
import shutil
import subprocess
import sys

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
MFCD, MFCD_MPI, MPIEXEC = sys.argv[1:4]


def main():
    try:
        import gmsh  # noqa: F401 (tools/mesh_body.py meshes with it)
    except ImportError:
        print("check_plane_file_mpi: the gmsh Python module is missing (tools/setup.sh "
              "--gmsh installs it): skipped")
        sys.exit(77)
    work = os.path.abspath("plane_file_mpi")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    # (.hdf5: check_mpi_run.py renames the deck's one '.h5' file, its output)
    ring = os.path.join(work, "ring.hdf5")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mesh_body.py"),
                        "--trusted", os.path.join(HERE, "ring.geo"), ring],
                       capture_output=True, text=True)
    if p.returncode != 0:
        print(p.stdout, p.stderr)
        sys.exit(1)
    print(p.stdout.strip())
    decks = [deck(work, "ring_crush_geo", ring, "ring_crush_file"),
             deck(work, "ring_crush_geo_rkpm", ring, "ring_crush_file_rkpm")]
    # a triangle naming a node past the last
    past = os.path.join(work, "ring_past.hdf5")
    shutil.copy(ring, past)
    with h5py.File(past, "r+") as f:
        t = f["/mesh/triangles"][...]
        t[len(t) // 2, 1] = f["/particles/x"].shape[0] + 1
        f["/mesh/triangles"][...] = t
    bad_past = deck(work, "ring_crush_geo", past, "ring_crush_file_past")
    # an RKPM body's file without its cells
    bare = os.path.join(work, "ring_bare.hdf5")
    shutil.copy(ring, bare)
    with h5py.File(bare, "r+") as f:
        del f["/cells"]
    bad_bare = deck(work, "ring_crush_geo_rkpm", bare, "ring_crush_file_bare")
    before = digest(ring)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run([sys.executable, os.path.join(HERE, "check_mpi_run.py"), "--ranks",
                        "2,3", "--t-end", "12.0e-6", "--restart", "2:3:100", "--checkpoints",
                        "100", "--made", "ring_crush_file", "--made", "ring_crush_file_rkpm",
                        "--bad-file", bad_past, "--bad-file", bad_bare, MFCD, MFCD_MPI,
                        MPIEXEC] + decks, cwd=work, env=env)
    ok = p.returncode == 0
    same = digest(ring) == before
    print(("[  OK  ] " if same else "[ FAIL ] ") + "plane_file: the user's file is the same "
          "bytes after the runs (read only)")
    sys.exit(0 if ok and same else 1)


def deck(work, name, mesh, out):
    """tests/mpi/NAME.nml with its ring read from the particle file mesh, as work/OUT.nml."""
    text = open(os.path.join(HERE, name + ".nml")).read()
    new = text.replace("shape = 'geo'", "shape = 'file'", 1).replace(
        "file = 'tests/mpi/ring.geo'", f"file = '{mesh}'", 1).replace(
        f"output/{name}.h5", f"output/{out}.h5", 1)
    assert new.count(mesh) == 1 and f"{out}.h5" in new, name
    path = os.path.join(work, out + ".nml")
    open(path, "w").write(new)
    return path


def digest(path):
    """The file's bytes' SHA-256."""
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


if __name__ == "__main__":
    main()
