#!/usr/bin/env python3
"""A 3D body from a tetrahedral mesh file (`&body shape = 'file'` on an HDF5 file with
/mesh/tetrahedra, as `tools/mesh_body.py --3d` writes it): a file is untrusted data, so
every way its columns can disagree is refused with exit 2, a message naming the file and
the fix, and nothing written; a good file runs, as elements and as RKPM particles.

The mesh: a cube of 3 x 3 x 3 nodes 5 mm apart, each of its 8 cells cut into the 6
tetrahedra of Kuhn's triangulation (48 in all), each ordered for a positive volume, and
each node's volume its quarter of the tetrahedra it belongs to. The bad files change one
thing each: a tetrahedron turned inside out (nodes 3 and 4 swapped), a node number past
the last node, a zero node number, /mesh/tetrahedra of 3 columns, no tetrahedra at all, a
node's volume off by 1% (the columns disagree), a node in no tetrahedron (its volume then
has no tetrahedra behind it), a NaN coordinate; and the index (/mesh/node_box,
/mesh/tet_box: the box of each block of 4096 rows, which mfcd_mpi's ranks read their parts
by) wrong: a box that misses a node, one that misses a tetrahedron's node, a NaN box, one
dataset without the other, the wrong number of blocks. A good index runs, and gives the
run without it to the bit.

Exit 77 (skipped) without h5py. Usage: test_mesh_files.py /path/to/mfcd
"""
import itertools
import os
import subprocess
import sys
import tempfile

MFCD = os.path.abspath(sys.argv[1])
results = []

DECK = """&run
  mode = 'dynamic'
  ndim = 3
/
&material
  name = 'steel'
  model = 'elastic'
  preset = 'paper_steel'
/
&body
  name = 'cube'
  shape = 'file'
  file = '{file}'
  basis = 'linear'
  material = 'steel'
  discretization = '{disc}'
  velocity = 0.0, 0.0, -1.0
/
&solver
  t_end = 2.0e-7
/
&output
  file = 'out/{stem}.h5'
/
"""


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "mesh_files." + name
          + ("" if cond else ": " + str(detail)[-800:]), flush=True)


def cube(np):
    """(x (27, 3), tetrahedra (48, 4) 0-based, positive volume)."""
    h = 0.005
    idx = {}
    x = []
    for k, j, i in itertools.product(range(3), repeat=3):
        idx[(i, j, k)] = len(x)
        x.append((i * h, j * h, k * h))
    x = np.array(x)
    tet = []
    for ci, cj, ck in itertools.product(range(2), repeat=3):
        for perm in itertools.permutations(range(3)):
            v = [ci, cj, ck]
            nodes = [idx[tuple(v)]]
            for a in perm:
                v = list(v)
                v[a] += 1
                nodes.append(idx[tuple(v)])
            tet.append(nodes)
    tet = np.array(tet)
    vol = volumes(np, x, tet)
    flip = vol < 0
    tet[flip] = tet[flip][:, [0, 1, 3, 2]]
    return x, tet


def volumes(np, x, tet):
    e1 = x[tet[:, 1]] - x[tet[:, 0]]
    e2 = x[tet[:, 2]] - x[tet[:, 0]]
    e3 = x[tet[:, 3]] - x[tet[:, 0]]
    return (e1[:, 0] * (e2[:, 1] * e3[:, 2] - e2[:, 2] * e3[:, 1])
            - e1[:, 1] * (e2[:, 0] * e3[:, 2] - e2[:, 2] * e3[:, 0])
            + e1[:, 2] * (e2[:, 0] * e3[:, 1] - e2[:, 1] * e3[:, 0])) / 6.0


def node_volumes(np, x, tet):
    v = volumes(np, x, tet)
    vol = np.zeros(x.shape[0])
    for k in range(4):
        np.add.at(vol, tet[:, k], 0.25 * v)
    return vol


def write(h5py, path, x, vol, tet, index=None):
    with h5py.File(path, "w") as f:
        f["particles/x"] = x
        f["particles/volume"] = vol
        if tet is not None:
            f["mesh/tetrahedra"] = tet
        for name, box in (index or {}).items():
            f["mesh/" + name] = box


def box_of(np, p):
    """The index's one box (low x, y, z, high x, y, z) of the points p (the cube's 27 nodes
    and 48 tetrahedra are one block of 4096 rows each)."""
    return np.concatenate([p.min(axis=0), p.max(axis=0)])[None, :]


def run(tmp, stem, file, disc):
    with open(os.path.join(tmp, stem + ".nml"), "w") as f:
        f.write(DECK.format(file=file, disc=disc, stem=stem))
    p = subprocess.run([MFCD, stem + ".nml"], cwd=tmp, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"), timeout=300)
    return p.returncode, p.stdout + p.stderr


def main():
    try:
        import h5py
        import numpy as np
    except ImportError:
        print("mesh_files: h5py or numpy missing: skipped")
        sys.exit(77)
    x, tet = cube(np)
    vol = node_volumes(np, x, tet)
    one = tet + 1
    with tempfile.TemporaryDirectory() as tmp:
        write(h5py, os.path.join(tmp, "good.h5"), x, vol, one)
        for disc in ("fem", "rkpm"):
            rc, out = run(tmp, "good_" + disc, "good.h5", disc)
            check(f"a good mesh file runs ({disc})", rc == 0 and os.path.exists(
                os.path.join(tmp, "out", f"good_{disc}.h5")), out[-800:])
        good_index = {"node_box": box_of(np, x), "tet_box": box_of(np, x)}
        write(h5py, os.path.join(tmp, "indexed.h5"), x, vol, one, good_index)
        rc, out = run(tmp, "indexed_fem", "indexed.h5", "fem")
        same = []
        if rc == 0:
            with h5py.File(os.path.join(tmp, "out", "good_fem.h5"), "r") as a, \
                    h5py.File(os.path.join(tmp, "out", "indexed_fem.h5"), "r") as b:
                for group in ("bodies", "history"):
                    a[group].visititems(lambda n, d, g=group: same.append(np.array_equal(
                        d[()], b[g + "/" + n][()])) if isinstance(d, h5py.Dataset) else None)
        check("a good index runs, every body and history dataset the bits of the run "
              "without it",
              rc == 0 and len(same) > 3 and all(same), out[-800:])
        # tools/mesh_body.py --reindex: the good file numbered in space with its index
        # (no gmsh): the same nodes, the same volume, the index holding every block, and it
        # runs
        tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                            "mesh_body.py")
        p = subprocess.run([sys.executable, tool, "--reindex", os.path.join(tmp, "good.h5"),
                            os.path.join(tmp, "reindexed.h5")], capture_output=True, text=True)
        ok = p.returncode == 0
        if ok:
            with h5py.File(os.path.join(tmp, "reindexed.h5"), "r") as f:
                rx, rt = f["particles/x"][()], f["mesh/tetrahedra"][()] - 1
                nb, tb = f["mesh/node_box"][()], f["mesh/tet_box"][()]
                rvol = f["particles/volume"][()]
            ok = (np.array_equal(np.unique(rx, axis=0), np.unique(x, axis=0))
                  and abs(rvol.sum() - vol.sum()) <= 1e-12 * vol.sum()
                  and np.all(rx.min(axis=0) >= nb[0, :3]) and np.all(rx.max(axis=0) <= nb[0, 3:])
                  and np.all(rx[rt].reshape(-1, 3).min(axis=0) >= tb[0, :3])
                  and sorted(map(tuple, np.sort(rx[rt], axis=1).reshape(len(rt), -1)))
                  == sorted(map(tuple, np.sort(x[tet], axis=1).reshape(len(tet), -1))))
            # in Morton order of the cells of 1024 a side over the extent (keys by hand)
            lo, e = rx.min(axis=0), float((rx.max(axis=0) - rx.min(axis=0)).max())
            keys = []
            for p_ in rx:
                c = [min(1023, int(((p_[a] - lo[a]) / e) * 1024.0)) for a in range(3)]
                keys.append(sum(((c[a] >> b) & 1) << (3 * b + a) for b in range(10)
                                for a in range(3)))
            ok = ok and keys == sorted(keys) and keys != list(range(len(keys)))
            rc, out = run(tmp, "reindexed_fem", "reindexed.h5", "fem")
            ok = ok and rc == 0
        check("mesh_body.py --reindex: the same mesh numbered in space, with its index, runs",
              ok, p.stdout + p.stderr)
        inside_out = one.copy()
        inside_out[7, [2, 3]] = inside_out[7, [3, 2]]
        past = one.copy()
        past[3, 1] = x.shape[0] + 1
        zero = one.copy()
        zero[5, 0] = 0
        off = vol.copy()
        off[13] *= 1.01
        nan_x = x.copy()
        nan_x[4, 1] = float("nan")
        # node 27 (the last) in no tetrahedron: the cube's 48 without those touching it
        spare = one[~np.any(one == x.shape[0], axis=1)]
        spare_vol = node_volumes(np, x, spare - 1)
        spare_vol[-1] = vol[-1]
        bad = [
            ("inside_out", x, vol, inside_out,
             ["tetrahedron 8 of /mesh/tetrahedra", "positive volume", "mesh_body.py --3d"]),
            ("node_past_end", x, vol, past,
             ["/mesh/tetrahedra names a node outside 1..27"]),
            ("node_zero", x, vol, zero, ["/mesh/tetrahedra names a node outside 1..27"]),
            ("three_columns", x, vol, one[:, :3], ["must be (ne, 4) node numbers"]),
            ("no_tetrahedra", x, vol, np.zeros((0, 4), dtype=np.int32),
             ["/mesh/tetrahedra is empty"]),
            ("volume_off", x, off, one,
             ["particle 14", "/particles/volume and /mesh/tetrahedra disagree"]),
            ("node_in_no_tetrahedron", x, spare_vol, spare,
             ["particle 27", "disagree"]),
            ("nan_coordinate", nan_x, vol, one, ["particle 5", "not a finite number"]),
        ]
        # the index wrong: the cube's nodes 10 mm in x from 0; a box to 5 mm misses node 3
        # (x = 10 mm: the nodes run x fastest); a tetrahedron box to 5 mm misses a node of
        # the first tetrahedron with one at x = 10 mm
        short = box_of(np, x)
        short[0, 3] = 5.0e-3
        first = int(np.argmax((x[tet] > 5.0e-3 + 1e-12)[:, :, 0].any(axis=1))) + 1
        nan_box = box_of(np, x)
        nan_box[0, 1] = float("nan")
        fix = ["mesh_body.py --3d", "delete /mesh/node_box and /mesh/tet_box"]
        bad += [
            ("index_node_outside", x, vol, one,
             ["particle 3 lies outside its block's box", "/mesh/node_box"] + fix,
             {"node_box": short, "tet_box": box_of(np, x)}),
            ("index_tet_outside", x, vol, one,
             [f"tetrahedron {first} has a node outside", "/mesh/tet_box"] + fix,
             {"node_box": box_of(np, x), "tet_box": short}),
            ("index_nan", x, vol, one, ["/mesh/tet_box has a box that is not finite"] + fix,
             {"node_box": nan_box, "tet_box": box_of(np, x)}),
            ("index_half", x, vol, one, ["needs both /mesh/node_box and /mesh/tet_box"],
             {"node_box": box_of(np, x)}),
            ("index_blocks", x, vol, one, ["must be (1, 6) and (1, 6)"],
             {"node_box": np.repeat(box_of(np, x), 2, axis=0), "tet_box": box_of(np, x)}),
        ]
        for name, bx, bvol, btet, expect, *index in bad:
            write(h5py, os.path.join(tmp, name + ".h5"), bx, bvol, btet,
                  index[0] if index else None)
            rc, out = run(tmp, name, name + ".h5", "fem")
            said = [e for e in expect if e not in out]
            check(f"{name}: exit 2, naming the file and what is wrong",
                  rc == 2 and not said and f"particle file '{name}.h5'" in out,
                  f"rc {rc}, missing {said}: {out[-900:]}")
            check(f"{name}: nothing written",
                  not os.path.exists(os.path.join(tmp, "out", name + ".h5")))
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    sys.exit(0 if results and all(results) else 1)


if __name__ == "__main__":
    main()
