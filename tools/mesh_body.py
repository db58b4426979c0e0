#!/usr/bin/env python3
"""Mesh a gmsh geometry (.geo) into an mfcd body file: the nodes as particles, the linear
triangles as a finite-element mesh, and each node's median-dual cell as its nodal
integration cell.

    .venv/bin/python tools/mesh_body.py --trusted input/hertz_sphere.geo \\
        output/meshes/sphere.h5 --set hc=0.1e-3 [--set a=0.4e-3 ...]

**Only for scripts you trust.** This script hands the .geo to gmsh's own interpreter, whose
language can run programs, write, read and delete files and end the process (SystemCall,
Printf > file, Save, Include, General.LogFileName, plugins, ...), and it runs gmsh without
mfcd's confinement. It refuses to start without --trusted, the user's word that the script
is theirs. A script from someone else is meshed by mfcd itself (`&body shape = 'geo'`): mfcd
reads only a subset of the language and builds the model through gmsh's API, in a thread
that can write no file (doc/deck.md, "What a gmsh script can do").

gmsh (PyPI `gmsh`, installed by `bash tools/setup.sh --gmsh`) reads the .geo with the
parser numbers given by --set (the script reads them as `If (!Exists(h)) h = ...; EndIf`),
meshes its surfaces with first-order triangles, and this script writes what mfcd reads with
`&body shape = 'file'` (doc/deck.md):

| dataset | shape (h5py) | meaning |
|---|---|---|
| /particles/x | (np, 2) | node coordinates (m): the particles of an RKPM body, the nodes of an FE body |
| /particles/volume | (np,) | each node's median-dual cell area (m^2): a third of every triangle touching it, so the volumes sum to the area of the mesh to round-off |
| /particles/loop, /particles/order | (np,) | boundary loop (0 interior) and position along it, counter-clockwise around the material (holes clockwise) |
| /mesh/triangles | (ne, 3) | node numbers (1-based rows of /particles/x), counter-clockwise |
| /cells/ptr, /cells/xy | (np+1,), (nv, 2) | node i's median-dual cell: the polygon xy[ptr[i]-1 : ptr[i+1]-1] (1-based CSR), counter-clockwise: the edge midpoints and triangle centroids around the node (and the node itself on the boundary). The cells tile the mesh exactly: SCNI integrates over them |

Only the nodes of the triangles are kept (gmsh's construction points are dropped). Exits 2
with a message on a bad geometry or an empty mesh.

With --3d the script's volumes are meshed with linear tetrahedra (a 3D deck's body, mesh
once and run many times: mfcd's shape = 'geo' meshes it again each run):

| dataset | shape (h5py) | meaning |
|---|---|---|
| /particles/x | (np, 3) | node coordinates (m) |
| /particles/volume | (np,) | each node's quarter of every tetrahedron it belongs to (m^3), summed node 1, 2, 3, 4 of each tetrahedron in turn |
| /mesh/tetrahedra | (ne, 4) | node numbers (1-based rows of /particles/x), positive volume: node 4 on the side of face (1, 2, 3) its right-hand normal points to |
| /mesh/node_box | (nb, 6) | the index: the box (x, y, z low, then high) of each block of 4096 rows of /particles/x (the last block the rest) |
| /mesh/tet_box | (nt, 6) | the box of the nodes of each block of 4096 rows of /mesh/tetrahedra |

    .venv/bin/python tools/mesh_body.py --reindex OLD.h5 NEW.h5

numbers a 3D mesh file written before the index existed (or by other tools: /particles/x,
/mesh/tetrahedra) in space and writes it with its index and each node's quarters of the
tetrahedra as its volume (no gmsh, no script run), so that mfcd_mpi's ranks read it in the
time of their parts.

The nodes and tetrahedra are numbered and oriented as mfcd numbers and orients its own mesh
of the script (shape = 'geo'), so the two bodies are the same bits (regression_geo_equivalence):
numbered in space (space_order: nodes by the Morton key of their cell in a grid of 1024
cubes a side, tetrahedra by their smallest node), so that each block of rows lies in a
small box and a rank of mfcd_mpi reads only the blocks its part meets (the index).

mfcd builds the same body in memory from the .geo itself (`&body shape = 'geo'`, when built
with gmsh: src/body/mesh_cells_m.f90 ports the functions below, bit for bit; the test
`regression_geo_equivalence` compares the two). This script remains the way to look at a
mesh, or to hand one to other tools.
"""
import argparse
import os
import sys

import h5py
import numpy as np


def mesh_geo(geo, numbers, quiet=True, dim=2):
    """(x (np, 2), triangles (ne, 3) 0-based, counter-clockwise) of the .geo's 2D mesh; with
    dim=3, (x (np, 3), tetrahedra (ne, 4) 0-based, positive volume) of its 3D mesh."""
    import gmsh
    # without the user's gmsh configuration files (~/.gmshrc, gmsh-options), as mfcd's
    # &body shape = 'geo' does (src/setup/gmsh_mesh_m.f90): the same .geo and numbers give the
    # same mesh whoever runs it
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0 if quiet else 1)
        for name, value in numbers.items():
            gmsh.parser.setNumber(name, [value])
        gmsh.merge(geo)   # merge, not open: open resets the parser numbers set above
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
        gmsh.model.mesh.generate(dim)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        types, _, nodes = gmsh.model.mesh.getElements(dim)
        version = gmsh.__version__
    finally:
        gmsh.finalize()
    if dim == 3:
        x, tet = used_nodes(tags, xyz, types, nodes, 4, 4, 3, f"{geo}: the mesh has no "
                            "tetrahedra (is there a Volume?)")
        # a positive volume (mfcd's mesh_from_tags: nodes 3 and 4 swapped where negative)
        v = tet_volumes(x, tet)
        if np.any(v == 0.0):
            raise ValueError(f"tetrahedron {int(np.argmax(v == 0.0)) + 1} of the mesh has "
                             "no volume (a degenerate element)")
        flip = v < 0
        tet[flip] = tet[flip][:, [0, 1, 3, 2]]
        x, tet = space_order(x, tet)
        return x, tet, version
    x, tri = used_nodes(tags, xyz, types, nodes, 2, 3, 2, f"{geo}: the mesh has no "
                        "triangles (is there a Plane Surface?)")
    # counter-clockwise
    a = signed_areas(x, tri)
    flip = a < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return x, tri, version


def used_nodes(tags, xyz, types, nodes, etype, nv, nd, empty):
    """(x (np, nd), elements (ne, nv) 0-based) of gmsh's elements of type etype (2: 3-node
    triangles, 4: 4-node tetrahedra) in gmsh's order, over the nodes they use in gmsh's
    order (np.unique), as mfcd's mesh_from_tags numbers them; ValueError(empty) if none."""
    elem = [np.asarray(n, dtype=np.int64).reshape(-1, nv)
            for t, n in zip(types, nodes) if t == etype]
    if not elem:
        raise ValueError(empty)
    elem = np.concatenate(elem)
    index = {int(t): k for k, t in enumerate(tags)}
    elem = np.vectorize(index.__getitem__)(elem)
    x = np.asarray(xyz, dtype=float).reshape(-1, 3)[:, :nd]
    used = np.unique(elem)
    renum = -np.ones(x.shape[0], dtype=np.int64)
    renum[used] = np.arange(used.size)
    return x[used], renum[elem]


INDEX_ROWS = 4096   # rows a block of the index (mfcd's mesh_cells_m index_rows)


def space_order(x, tet):
    """(x, tet) numbered in space, as mfcd's space_order (src/body/mesh_cells_m.f90) does,
    the same doubles and order: the nodes sorted (stably) by the Morton key of their cell
    in a grid of 1024 cubes a side over the mesh's extent (c = floor((x - lo)/e*1024), at
    most 1023, e the largest extent; bits of c_x, c_y, c_z interleaved, x's lowest), then
    the tetrahedra (stably) by their smallest node, each keeping its nodes' order."""
    lo = x.min(axis=0)
    ext = float((x.max(axis=0) - lo).max())
    key = np.zeros(x.shape[0], dtype=np.int64)
    if ext > 0.0:
        c = np.minimum(1023, np.floor(((x - lo) / ext) * 1024.0).astype(np.int64))
        for bit in range(10):
            for a in range(3):
                key |= ((c[:, a] >> bit) & 1) << (3 * bit + a)
    order = np.argsort(key, kind="stable")
    renum = np.empty_like(order)
    renum[order] = np.arange(order.size)
    tet = renum[tet]
    torder = np.argsort(tet.min(axis=1), kind="stable")
    return x[order], tet[torder]


def mesh_index(x, tet):
    """(node_box (nb, 6), tet_box (nt, 6)): the box (low, high) of each block of
    INDEX_ROWS nodes, and of the nodes of each block of INDEX_ROWS tetrahedra."""
    def boxes(pts_of_block, n):
        out = np.empty(((n + INDEX_ROWS - 1) // INDEX_ROWS, 6))
        for k in range(out.shape[0]):
            p = pts_of_block(slice(k * INDEX_ROWS, min(n, (k + 1) * INDEX_ROWS)))
            out[k, :3] = p.min(axis=0)
            out[k, 3:] = p.max(axis=0)
        return out
    nbox = boxes(lambda s: x[s], x.shape[0])
    tbox = boxes(lambda s: x[tet[s].ravel()], tet.shape[0])
    return nbox, tbox


def tet_volumes(x, tet):
    """Signed volumes of the tetrahedra, as mfcd's tet_volume computes them (the same
    operations in the same order: the same doubles)."""
    e1 = x[tet[:, 1]] - x[tet[:, 0]]
    e2 = x[tet[:, 2]] - x[tet[:, 0]]
    e3 = x[tet[:, 3]] - x[tet[:, 0]]
    return (e1[:, 0] * (e2[:, 1] * e3[:, 2] - e2[:, 2] * e3[:, 1])
            - e1[:, 1] * (e2[:, 0] * e3[:, 2] - e2[:, 2] * e3[:, 0])
            + e1[:, 2] * (e2[:, 0] * e3[:, 1] - e2[:, 1] * e3[:, 0])) / 6.0


def write_body_3d(path, x, tet, attrs):
    """The particle file of a tetrahedral mesh: the nodes, each node's quarter of every
    tetrahedron it belongs to (summed node 1, 2, 3, 4 of each in turn, as mfcd sums them),
    the tetrahedra (1-based)."""
    v = tet_volumes(x, tet)
    vol = np.zeros(x.shape[0])
    for k in range(4):
        np.add.at(vol, tet[:, k], 0.25 * v)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with h5py.File(path, "w") as f:
        f["particles/x"] = x
        f["particles/volume"] = vol
        f["mesh/tetrahedra"] = (tet + 1).astype(np.int32)
        f["mesh/node_box"], f["mesh/tet_box"] = mesh_index(x, tet)
        for k, val in attrs.items():
            f.attrs[k] = val
    return vol, v


def signed_areas(x, tri):
    p0, p1, p2 = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    return 0.5 * ((p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1])
                  - (p2[:, 0] - p0[:, 0]) * (p1[:, 1] - p0[:, 1]))


def boundary_loops(tri):
    """Closed boundary loops as lists of node numbers: the directed triangle edges that no
    other triangle has reversed, chained; with counter-clockwise triangles each runs with
    the material on its left."""
    edges = {}
    for t in tri:
        for k in range(3):
            edges[(int(t[k]), int(t[(k + 1) % 3]))] = True
    nxt = {a: b for (a, b) in edges if (b, a) not in edges}
    loops = []
    while nxt:
        start = min(nxt)
        loop = [start]
        node = nxt.pop(start)
        while node != start:
            loop.append(node)
            if node not in nxt:
                raise ValueError("the boundary is not a set of closed loops (a node where "
                                 "two boundary chains meet?)")
            node = nxt.pop(node)
        loops.append(loop)
    return loops


def dual_cells(x, tri):
    """Median-dual cell of every node, counter-clockwise: around the node, for each
    triangle (i, a, b) in turn the midpoint of i-a, the centroid and the midpoint of i-b;
    a boundary node's cell starts and ends at the node itself."""
    fans = [[] for _ in range(x.shape[0])]
    for t in tri:
        for k in range(3):
            i, a, b = int(t[k]), int(t[(k + 1) % 3]), int(t[(k + 2) % 3])
            fans[i].append((a, b, x[t].mean(axis=0)))
    ptr, xy = [1], []
    for i, fan in enumerate(fans):
        by_a = {a: (a, b, c) for a, b, c in fan}
        bs = {b for _, b, _ in fan}
        starts = [a for a in by_a if a not in bs]
        boundary = bool(starts)
        a = starts[0] if boundary else fan[0][0]
        poly = [x[i]] if boundary else []
        seen = 0
        while a in by_a and seen < len(fan):
            _, b, c = by_a[a]
            poly += [0.5 * (x[i] + x[a]), c]
            seen += 1
            a = b
            if not boundary and a == fan[0][0]:
                break
        if boundary:
            poly.append(0.5 * (x[i] + x[a]))
        if seen != len(fan):
            raise ValueError(f"node {i + 1}: its triangles do not form one fan (a pinched "
                             "mesh)")
        xy += poly
        ptr.append(ptr[-1] + len(poly))
    return np.array(ptr, dtype=np.int64), np.array(xy)


def polygon_area(p):
    return 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


def write_body(path, x, tri, loops, ptr, xy, attrs):
    np_ = x.shape[0]
    area = signed_areas(x, tri)
    vol = np.zeros(np_)
    for k in range(3):
        np.add.at(vol, tri[:, k], area / 3.0)
    loop = np.zeros(np_, dtype=np.int32)
    order = np.zeros(np_, dtype=np.int32)
    for k, lp in enumerate(loops, start=1):
        loop[lp] = k
        order[lp] = np.arange(len(lp))
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with h5py.File(path, "w") as f:
        f["particles/x"] = x
        f["particles/volume"] = vol
        f["particles/loop"] = loop
        f["particles/order"] = order
        f["mesh/triangles"] = (tri + 1).astype(np.int32)
        f["cells/ptr"] = ptr.astype(np.int32)
        f["cells/xy"] = xy
        for k, v in attrs.items():
            f.attrs[k] = v
    return vol, area


def reindex(src, out):
    """The 3D mesh file src written to out numbered in space with its index; exit 2 on a
    file that is not one (mfcd checks the rest when it reads out)."""
    try:
        with h5py.File(src, "r") as f:
            x = np.asarray(f["particles/x"][()], dtype=float)
            tet = np.asarray(f["mesh/tetrahedra"][()], dtype=np.int64)
            attrs = dict(f.attrs)
    except (OSError, KeyError) as e:
        print(f"mesh_body: error: {src}: not a 3D mesh file with /particles/x and "
              f"/mesh/tetrahedra ({e})", file=sys.stderr)
        return 2
    if x.ndim != 2 or x.shape[1] != 3 or tet.ndim != 2 or tet.shape[1] != 4 or \
            tet.size == 0 or tet.min() < 1 or tet.max() > x.shape[0]:
        print(f"mesh_body: error: {src}: /particles/x must be (np, 3) and /mesh/tetrahedra "
              f"(ne, 4) node numbers in 1..np", file=sys.stderr)
        return 2
    x, tet = space_order(x, tet - 1)
    attrs["reindexed_from"] = os.path.basename(src)
    vol, v = write_body_3d(out, x, tet, attrs)
    print(f"mesh_body: {out}: {x.shape[0]} nodes, {tet.shape[0]} tetrahedra numbered in "
          f"space, with the index; volume {v.sum():.6e} m^3")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("geo")
    ap.add_argument("out")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a gmsh parser number, e.g. h=0.5e-3 (repeat for more)")
    ap.add_argument("--3d", dest="three_d", action="store_true",
                    help="mesh the script's volumes with linear tetrahedra (a 3D body: "
                         "/particles/x (np, 3), /particles/volume, /mesh/tetrahedra)")
    ap.add_argument("--trusted", action="store_true",
                    help="the script is yours: gmsh's interpreter may run it (it can run "
                         "programs and write files; untrusted scripts: &body shape = 'geo')")
    ap.add_argument("--reindex", action="store_true",
                    help="GEO is a 3D mesh file (/particles/x, /mesh/tetrahedra): write it "
                         "to OUT numbered in space with its index (no gmsh)")
    a = ap.parse_args(argv)
    if a.reindex:
        return reindex(a.geo, a.out)
    if not a.trusted:
        print(f"mesh_body: error: {a.geo}: not run without --trusted: gmsh's interpreter "
              "would run the whole .geo language, which can run programs and write, read "
              "and delete files; give --trusted for a script of your own, or let mfcd mesh "
              "it (&body shape = 'geo' reads a safe subset, doc/deck.md)", file=sys.stderr)
        return 2
    numbers = {}
    for item in a.set:
        name, _, value = item.partition("=")
        try:
            numbers[name.strip()] = float(value)
        except ValueError:
            print(f"mesh_body: error: --set {item!r}: give NAME=NUMBER", file=sys.stderr)
            return 2
    try:
        import gmsh  # noqa: F401
    except ImportError:
        print("mesh_body: error: the gmsh Python module is missing: run "
              "`bash tools/setup.sh --gmsh` (PyPI gmsh into .venv)", file=sys.stderr)
        return 2
    if a.three_d:
        try:
            x, tet, version = mesh_geo(a.geo, numbers, dim=3)
        except (ValueError, Exception) as e:   # gmsh raises plain Exceptions
            print(f"mesh_body: error: {a.geo}: {e}", file=sys.stderr)
            return 2
        attrs = {"source": os.path.basename(a.geo), "gmsh_version": version,
                 "parameters": "; ".join(f"{k}={v:g}" for k, v in numbers.items())}
        vol, v = write_body_3d(a.out, x, tet, attrs)
        print(f"mesh_body: {a.out}: {x.shape[0]} nodes, {tet.shape[0]} tetrahedra; volume "
              f"{v.sum():.6e} m^3, nodal volumes sum to {vol.sum():.6e}")
        return 0
    try:
        x, tri, version = mesh_geo(a.geo, numbers)
        loops = boundary_loops(tri)
        ptr, xy = dual_cells(x, tri)
    except (ValueError, Exception) as e:   # gmsh raises plain Exceptions
        print(f"mesh_body: error: {a.geo}: {e}", file=sys.stderr)
        return 2
    attrs = {"source": os.path.basename(a.geo), "gmsh_version": version,
             "parameters": "; ".join(f"{k}={v:g}" for k, v in numbers.items())}
    vol, area = write_body(a.out, x, tri, loops, ptr, xy, attrs)
    cells = sum(polygon_area(xy[ptr[i] - 1:ptr[i + 1] - 1]) for i in range(x.shape[0]))
    print(f"mesh_body: {a.out}: {x.shape[0]} nodes, {tri.shape[0]} triangles, {len(loops)} "
          f"boundary loop(s); area {area.sum():.6e} m^2, nodal volumes sum to "
          f"{vol.sum():.6e}, dual cells to {cells:.6e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
