#!/usr/bin/env python3
"""A 3D body from a tetrahedral mesh file read per part by mfcd_mpi (src/setup/tet_file_m.f90):
each rank streams the file and keeps its share of the nodes and tetrahedra and the region
its part needs, never the whole mesh (doc/parallel.md, "Mesh files read per part").

Meshed once by tools/mesh_body.py --3d (the gmsh Python module of .venv; exit 77, skipped,
without it), the decks given those files (&body shape = 'file'), then
tests/mpi/check_mpi_run.py on 2-4 ranks: every dataset the serial mfcd writes, /bodies'
facets too (gathered from the ranks in the whole mesh's order), bit for bit, and each body
read per part (--made: no rank read all its nodes):
- the Taylor quarter of input/taylor_bar_3d_fem_geo.nml (h = 1.5 mm) on its rigid target,
  2 us; a checkpoint written on 2 ranks continued on 3; the same deck with supports too
  small for det(M) (support_factor 0.5) refused on 2, 4 and 6 ranks with the serial message;
- the same bar on a deformable block of tetrahedra (its deforming master: detection both
  ways, the bar's side taking its det(M) plateau, surface median and whole surface from the
  file over the ranks), and the block on the bar (the bar the master), 2 us; the bar
  (h = 1 mm) by RKPM over the tetrahedra's median-dual cells, lifted 0.1 mm off its rigid
  target by &body translate, 2 us;
- the tube of input/tube_crush_coarse.nml (h = 0.7 mm) between its rigid floor and ram with
  its self-contact, 2 us (a rank whose region meets no &bc box asks the file whether the
  whole body has a node there).
The bar's file without its index (every rank reads it whole; the log says so) on 2 and 3
ranks, the same checks. Then a file with one tetrahedron turned inside out, and one whose index (/mesh/node_box:
the box of each block of 4096 nodes, by which a rank reads only the blocks its part meets)
misses a node: the serial run and 2 and 3 ranks exit 2 with the serial message naming it,
writing nothing.

Usage: check_mesh_file_mpi.py MFCD MFCD_MPI MPIEXEC
"""
import os
import re
import shutil
import subprocess
import sys

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
MFCD, MFCD_MPI, MPIEXEC = sys.argv[1:4]
H = "1.5e-3"


def main():
    try:
        import gmsh  # noqa: F401 (tools/mesh_body.py meshes with it)
    except ImportError:
        print("check_mesh_file_mpi: the gmsh Python module is missing (tools/setup.sh "
              "--gmsh installs it): skipped")
        sys.exit(77)
    work = os.path.abspath("mesh_file_mpi")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    mesh = os.path.join(work, "taylor_quarter.hdf5")
    text = from_file(work, "taylor_bar_3d_fem_geo", "taylor_bar_quarter.geo", mesh,
                     [f"h={H}"])
    tube = os.path.join(work, "tube.hdf5")
    tube_text = from_file(work, "tube_crush_coarse", "tube_crush.geo", tube,
                          ["R=10.0e-3", "t=1.0e-3", "L=12.0e-3", "H=4.25e-3", "a=0.1e-3",
                           "h=0.7e-3"])
    deck = os.path.join(work, "taylor_bar_3d_fem_file.nml")
    open(deck, "w").write(text)
    small = os.path.join(work, "taylor_bar_3d_fem_file_small_support.nml")
    open(small, "w").write(text.replace("support_factor = 2.0, 2.0, 2.0",
                                        "support_factor = 0.5, 0.5, 0.5", 1))
    # the target deformable (tetrahedra): the bar's master, then the bar the block's
    block = text.replace("  name = 'target'\n  role = 'rigid'",
                         "  name = 'target'\n  discretization = 'fem'\n  material = 'steel'", 1)
    assert block != text
    on_block = os.path.join(work, "taylor_bar_3d_fem_file_on_block.nml")
    open(on_block, "w").write(block)
    swapped = block.replace("master = 'target'\n  slave = 'bar'",
                            "master = 'bar'\n  slave = 'target'", 1)
    assert swapped != block
    under_block = os.path.join(work, "taylor_bar_3d_fem_file_master.nml")
    open(under_block, "w").write(swapped)
    # the bar by RKPM over the tetrahedra's median-dual cells (each rank reads its region's
    # tetrahedra for its cells), on a finer mesh (1 mm): an RKPM region reaches some 8
    # longest edges beyond the rank's box, the whole 1.5 mm bar on 3 ranks
    fine = os.path.join(work, "taylor_quarter_1mm.hdf5")
    rkpm = from_file(work, "taylor_bar_3d_fem_geo", "taylor_bar_quarter.geo", fine,
                     ["h=1.0e-3"])
    rkpm = rkpm.replace("discretization = 'fem'", "discretization = 'rkpm'", 1)
    # (lifted 0.1 mm off its target by &body translate: every row a rank reads of the file
    # is moved as the serial body is; the contact after 0.5 us)
    rkpm = rkpm.replace("velocity = 0.0, 0.0, -200.0",
                        "velocity = 0.0, 0.0, -200.0\n  translate = 0.0, 0.0, 0.1e-3", 1)
    assert "'rkpm'" in rkpm and "translate" in rkpm
    bar_rkpm = os.path.join(work, "taylor_bar_3d_rkpm_file.nml")
    open(bar_rkpm, "w").write(rkpm)
    tube_self = os.path.join(work, "tube_crush_file_self.nml")
    open(tube_self, "w").write(tube_text.replace(
        "&solver", "&contact\n  master = 'tube'\n  slave = 'tube'\n/\n&solver", 1))
    # (as check_mpi_run.py runs mpiexec: a CI container is root)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    run = [sys.executable, os.path.join(HERE, "check_mpi_run.py"), "--t-end", "2.0e-6"]
    p = subprocess.run(run + ["--ranks", "2,3,4", "--made", "taylor_bar_3d_fem_file",
                              "--restart", "2:3:8", "--bad-particle", small, MFCD, MFCD_MPI,
                              MPIEXEC, deck], cwd=work, env=env)
    ok = p.returncode == 0
    p = subprocess.run(run + ["--ranks", "2,3", "--made", "taylor_bar_3d_fem_file_on_block",
                              "--made", "taylor_bar_3d_fem_file_master", "--made",
                              "taylor_bar_3d_rkpm_file", MFCD, MFCD_MPI, MPIEXEC, on_block,
                              under_block, bar_rkpm], cwd=work, env=env)
    ok = p.returncode == 0 and ok
    p = subprocess.run(run + ["--ranks", "2,3,4", "--made", "tube_crush_file_self", MFCD,
                              MFCD_MPI, MPIEXEC, tube_self], cwd=work, env=env)
    ok = p.returncode == 0 and ok
    # the bar's file without its index (one written before it, or by other tools): every
    # rank reads the whole file for its part, the same bits, and the log says so
    plain = os.path.join(work, "taylor_quarter_plain.hdf5")
    shutil.copy(mesh, plain)
    with h5py.File(plain, "r+") as f:
        del f["/mesh/node_box"], f["/mesh/tet_box"]
    plain_deck = os.path.join(work, "taylor_bar_3d_fem_file_plain.nml")
    open(plain_deck, "w").write(text.replace(mesh, plain))
    p = subprocess.run(run + ["--ranks", "2,3", "--made", "taylor_bar_3d_fem_file_plain",
                              MFCD, MFCD_MPI, MPIEXEC, plain_deck], cwd=work, env=env)
    ok = p.returncode == 0 and ok
    p = subprocess.run([MPIEXEC, "--oversubscribe", "-n", "2", MFCD_MPI, plain_deck],
                       cwd=work, env=env, capture_output=True, text=True, timeout=300)
    said = "has no index (/mesh/node_box, /mesh/tet_box)" in p.stdout
    print(("[  OK  ] " if said else "[ FAIL ] ") + "mesh_file: a file without its index "
          "is said so on ranks" + ("" if said else f": {p.stdout[-600:]}"))
    ok = said and ok
    ok = refused(work, mesh, text, env, "turned", turned_tetrahedron,
                 "tetrahedron 100 of /mesh/tetrahedra") and ok
    with h5py.File(mesh, "r") as f:
        late = 3 * f["/mesh/tetrahedra"].shape[0] // 4 + 1
    ok = refused(work, mesh, text, env, "turned_late", turned_late,
                 f"tetrahedron {late} of /mesh/tetrahedra") and ok
    # (the index the ranks read their parts by: checked by the serial run and every rank)
    ok = refused(work, mesh, text, env, "squeezed", squeezed_index,
                 "lies outside its block's box in the index /mesh/node_box") and ok
    sys.exit(0 if ok else 1)


def from_file(work, name, geo, mesh, numbers):
    """input/NAME.nml's body meshed from input/GEO into mesh, the deck's text given it."""
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mesh_body.py"),
                        "--trusted", "--3d"] + [f"--set={v}" for v in numbers]
                       + [os.path.join(ROOT, "input", geo), mesh], capture_output=True,
                       text=True)
    if p.returncode != 0:
        print(p.stdout, p.stderr)
        sys.exit(1)
    print(p.stdout.strip())
    text = open(os.path.join(ROOT, "input", name + ".nml")).read()
    text = text.replace("shape = 'geo'", "shape = 'file'", 1)
    text = text.replace(f"file = 'input/{geo}'", f"file = '{mesh}'", 1)
    assert mesh in text, name
    return re.sub(r"^\s*geo_(names|values)\s*=.*\n", "", text, flags=re.M)


def turned_tetrahedron(f):
    """Tetrahedron 100 turned inside out (in the first rank's share)."""
    t = f["/mesh/tetrahedra"][...]
    t[99, [2, 3]] = t[99, [3, 2]]
    f["/mesh/tetrahedra"][...] = t


def turned_late(f):
    """The tetrahedron three quarters down the file turned inside out (in the last rank's
    share on 2 and 3 ranks: the ranks' first wrong rows reduced to the serial one)."""
    t = f["/mesh/tetrahedra"][...]
    k = 3 * t.shape[0] // 4
    t[k, [2, 3]] = t[k, [3, 2]]
    f["/mesh/tetrahedra"][...] = t


def squeezed_index(f):
    """The index's first block of nodes squeezed below the bar's top tenth (z): the nodes
    above lie outside it, numbered last (z's is the Morton key's highest bit), so found by
    the last ranks."""
    box = f["/mesh/node_box"][...]
    box[0, 5] = box[0, 2] + 0.9 * (box[0, 5] - box[0, 2])
    f["/mesh/node_box"][...] = box


def refused(work, mesh, text, env, stem, edit, words):
    """The file changed by edit: refused by every run, the same words."""
    bad = os.path.join(work, f"taylor_quarter_{stem}.hdf5")
    shutil.copy(mesh, bad)
    with h5py.File(bad, "r+") as f:
        edit(f)
    deck = os.path.join(work, f"{stem}.nml")
    open(deck, "w").write(text.replace(mesh, bad).replace(
        "file = 'output/taylor_bar_3d_fem_geo.h5'", f"file = '{stem}_out.h5'"))
    results = []
    before = set(os.listdir(work))
    p = subprocess.run([MFCD, deck], cwd=work, env=env, capture_output=True, text=True,
                       timeout=120)
    said = [l.split("mfcd: error: ", 1)[1] for l in p.stderr.splitlines()
            if l.startswith("mfcd: error: ")]
    good = p.returncode == 2 and len(said) == 1 and words in said[0]
    results.append(good)
    print(("[  OK  ] " if good else "[ FAIL ] ") + f"mesh_file ({stem}): the serial run "
          f"refuses it, saying '{words}'" + ("" if good else f": {p.returncode} {p.stderr}"))
    for n in (2, 3):
        p = subprocess.run([MPIEXEC, "--oversubscribe", "-n", str(n), MFCD_MPI, deck],
                           cwd=work, env=env, capture_output=True, text=True, timeout=120)
        made = set(os.listdir(work)) - before
        good = bool(said) and p.returncode == 2 and said[0] in p.stderr and not made
        results.append(good)
        print(("[  OK  ] " if good else "[ FAIL ] ") + f"mesh_file ({stem}), {n} ranks: "
              "exits 2 with the serial run's message, nothing written"
              + ("" if good else f": {p.returncode} {p.stderr[-800:]} {made}"))
    return all(results)


if __name__ == "__main__":
    main()
