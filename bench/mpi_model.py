#!/usr/bin/env python3
"""The communication model of doc/parallel.md drawn: weak-scaling efficiency of mfcd_mpi
against the number of ranks, for 10^5 nodes per rank (10^8 at 10^3 ranks), from the counts
measured on this machine, with the measured 2-rank points beside it.

    .venv/bin/python bench/mpi_model.py [OUT.png]   (default doc/figures/mpi_scaling_model.png)
    .venv/bin/python bench/mpi_model.py --3d [OUT.png]
                     (3D, with the output and the set-up's memory: mpi_scaling_model_3d.png)

Per step and rank (CST4 part of n nodes in a square; doc/parallel.md, "A model"):
  work      113 ns per triangle-step (measured: 4.9 ms for the 43,200 triangles of the
            paper's FEM Taylor mesh on one core), 2 n triangles;
  halos     three neighbour exchanges: 4 sqrt(n) ghost nodes at 32 B twice, 8 sqrt(n) ghost
            points at 40 B (the counts of the 2-rank runs, scaled by the part's perimeter);
  reductions five MPI_Allreduce of a few numbers, log2(P) stages each;
  contact   with a deforming master: 6 sqrt(n) ghost master particles (a strip of the ghost
            width along the rank's share of the contact face) at 32 B, four exchanges a step,
            and six more reductions.
Network: LATENCY per message or reduction stage, BANDWIDTH per rank (assumed, typical of an
InfiniBand cluster; change them below). Prints the table it draws.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "post"))
from mfcd_style import figure_style  # noqa: E402

N = 1.0e5                 # nodes per rank
NS_PER_TRIANGLE = 113e-9  # s per triangle-step, measured (doc/parallel.md)
LATENCY = 2.0e-6          # s per message or reduction stage (assumed)
BANDWIDTH = 10.0e9        # B/s per rank (assumed)
# measured weak-scaling efficiencies on 2 ranks (bench/mpi_scaling.sh, doc/parallel.md)
MEASURED = {"rigid master (FEM Taylor bar)": 0.98, "deforming master (slab and block)": 0.95}


def step_times(p, contact):
    """Work and communication time of one step on p ranks (s)."""
    work = NS_PER_TRIANGLE * 2.0 * N
    if p == 1:
        return work, 0.0
    r = math.sqrt(N)
    halo_bytes = 2 * 32 * 4 * r + 40 * 8 * r
    comm = 3 * LATENCY + halo_bytes / BANDWIDTH
    stages = math.ceil(math.log2(p))
    comm += 5 * stages * LATENCY
    if contact:
        comm += 4 * (LATENCY + 32 * 6 * r / BANDWIDTH) + 6 * stages * LATENCY
    return work, comm


# ---- 3D (issue 24): TL-RKPM parts of n particles in a cube, from the 3D Taylor bench ----
# (bench/mpi_scaling.sh's taylor_bar_3d_rkpm_bench.nml on 1 and 2 ranks; doc/parallel.md,
# "A model in 3D"). Measured values are marked so; the rest is assumed.
# measured 2026-11-27 (bench/results/mpi_scaling_2026-11-27_165018.md, AMD EPYC guest):
# 31.08 s for 300 steps of 37,467 particles on 1 rank; on 2 ranks 828 ghost nodes and 828
# ghost points across a cut of 207 particles, 1.392e5 B and 1.196e5 B moved per step; a
# snapshot of the bar 5,994,720 B
NS_PER_PARTICLE_3D = 2.77e-6  # s per particle-step, 1 rank, 1 thread (measured)
GHOST_LAYERS_3D = (4.0, 4.0)  # ghost nodes, points per particle of a cut face (measured)
BYTES_GHOST_3D = (168.0, 144.0)  # B per ghost node, point and step (measured)
SNAP_BYTES_3D = 160.0         # B per particle of a snapshot's gathered fields (measured)
MEASURED_3D = 0.82            # weak-scaling efficiency on 2 ranks (measured, this guest)
# a rank's memory, measured 2026-11-29 and 2026-11-30 on the bench's bar (109 nodes a
# point; doc/parallel.md, "Against rigid masters the time loop holds nothing of the whole
# body" and "The set-up's solid numbered over the region"): a fixed share; at the split
# (the run's peak) its part's rows and their transpose, nothing of the whole body (0.73 GB
# a rank on 2, 4 and 8 ranks at 18,700 particles a rank); at the set-up's peak its
# region's rows and what the set-up still holds of the whole body (the bodies as
# generated, the builders' arrays over every particle and point before the region's cut:
# 428-431 MiB a rank on 2 ranks, 440-460 on 8, mfcd_mpi's logged peaks in
# bench/mpi_weak_3d.sh's runs; 0.11 kB a particle of the whole run at the end ranks, 0.16
# at the interior ones; 0.44 kB before the set-up's solid was numbered over the region)
FIXED_BYTES_3D = 0.07e9       # B per rank whatever its part (runtime, Open MPI, HDF5)
PART_BYTES_3D = 35.0e3        # B per particle of the part at the split's peak (measured)
SETUP_PART_BYTES_3D = 20.0e3  # B per particle of the part at the set-up's peak (measured)
WHOLE_BYTES_3D = 0.13e3       # B per particle of the whole body at the set-up (measured)
# measured 2026-11-30 on a lent 16-core machine (one socket; doc/parallel.md, "3D on 16
# cores"): the loop's weak efficiency of the bench's bar 30 mm a rank (18,700 particles a
# rank, 50 steps) on 1-16 ranks; 16 independent one-rank runs at once took 6.29 s a run
# against 4.73 s alone (the socket's memory bandwidth shared: a node full of ranks steps
# at NODE_SHARE_3D of one rank alone, whatever the messages); in weak scaling the set-up
# grew from 4 to 16 ranks (parts of the same shape) by 7-8 s beyond what 4 and 16 runs at
# once cost, for 224,000 more particles of the whole body (SETUP_WHOLE_S_3D: 20-35 us a
# particle, 1 -> 16 ranks and 4 -> 16 ranks; not broken down: no whole-body routine leads
# a profile, page clearing of fresh memory grows most)
MEASURED_WEAK_16 = {1: 1.00, 2: 0.87, 4: 0.73, 8: 0.69, 16: 0.56}
NODE_SHARE_3D = 0.75          # a full node's step against one rank alone (measured)
RANKS_PER_NODE = 16           # the lent machine's cores (nodes full from this count on)
SETUP_WHOLE_S_3D = 25.0e-6    # s of set-up per particle of the whole body (measured, 20-35)
FS_BANDWIDTH = 100.0e9        # B/s of a parallel file system, aggregate (assumed)
# a body of tetrahedra from a mesh file (tools/mesh_body.py --3d, or a gmsh script meshed
# once by rank 0): every rank streams the whole file some six times for its share and
# region (tet_file_m; no index by space in the file); measured 2026-11-30, the Taylor
# quarter at 0.3 mm (38,358 nodes, 193,438 tetrahedra) on 2 and 4 ranks: 24.7 MB read by
# each rank other than 0 (/proc/PID/io rchar, less a generated body's 0.15 MB)
MESH_READ_BYTES_3D = 640.0    # B read by every rank per node of the whole mesh (measured)
# since 2026-12-01 a file numbered in space with its index (/mesh/node_box, /mesh/tet_box:
# what tools/mesh_body.py --3d and mfcd_mpi's own meshes write) is read per part: each rank
# its shares of the rows for the whole file's checks and the blocks near its part; measured
# the same day on the weak bench's bar (bench/mpi_weak_3d.sh MESH=1: 14,742 nodes a rank)
# on 2, 4 and 8 ranks: 10.5-12.2 MB a rank whatever the whole mesh (16.7, 30.7, 57.9 MB
# before), at most 12.2 MB less 0.15 MB = 820 B a node of the part
MESH_READ_PART_BYTES_3D = 820.0  # B read by a rank per node of its part (measured)
RANK_READ_BANDWIDTH = 1.0e9   # B/s one rank reads from the file system (assumed)
MEM_PER_RANK = 4.0 * 2 ** 30  # B of memory per rank (a core's share of a node, assumed)
# a deforming master's or a self-contact's side took the whole closed surface once at the
# set-up until 2026-12-01 (dynamic_setup_m side_facts: the facets, and the lean surface's
# facets, vertices' places, edge partners, vertices' numbers and positions, about two
# facets a vertex), until the split kept each rank's own facets; since then the facets with
# a vertex in the rank's region only (side_surface_m), the same bytes a facet kept: from
# the arrays' sizes, not measured
SIDE_SURFACE_BYTES_3D = 12.0 + 36.0 + 0.5 * (4.0 + 24.0)  # B per facet of the whole surface
# facets per particle of the whole body: a cube of N lattice particles has 6 N^(2/3) on its
# faces, two facets each; the weak bench's thin quarter bar 0.54 (measured, mfcd_mpi's log)
THIN_BAR_FACETS = 0.54
# the most facets near a rank's region against the whole surface's share a rank (W / p):
# the weak bench's bar with its self-contact (SELF=1 bash bench/mpi_weak_3d.sh, 18,700
# particles a rank, 2026-12-01: doc/parallel.md) 11,340 of 78,476 on 8 ranks (9,810 a
# share), the same 11,340 on 4: an interior rank's region; a larger part has a thinner
# halo against it, so this overstates 10^5-10^6 a rank
NEAR_REGION_FACTOR = 1.16
STEPS_PER_SNAPSHOT = 1000     # steps between snapshots (assumed)


def step_times_3d(p, n):
    """Work and halo/reduction time of one 3D step on p ranks of n particles each (s): a
    part is a cube, its ghosts the layers on its six faces (fewer faces on few ranks: the
    faces are cut only where another part lies, min(6, 2 log2 p) of them)."""
    work = NS_PER_PARTICLE_3D * n
    if p == 1:
        return work, 0.0
    faces = min(6.0, 2.0 * math.log2(p))
    area = n ** (2.0 / 3.0)
    halo_bytes = faces * area * (GHOST_LAYERS_3D[0] * BYTES_GHOST_3D[0]
                                 + GHOST_LAYERS_3D[1] * BYTES_GHOST_3D[1])
    comm = 3 * LATENCY + halo_bytes / BANDWIDTH
    comm += 5 * math.ceil(math.log2(p)) * LATENCY
    return work, comm


def peak_bytes_3d(p, n, whole=WHOLE_BYTES_3D):
    """A rank's peak memory (B) on p ranks of n particles each: the fixed share and the
    larger of the split's (its part) and the set-up's (its part's share there and the
    whole body's p n particles at `whole` B each)."""
    return FIXED_BYTES_3D + max(n * PART_BYTES_3D, n * SETUP_PART_BYTES_3D + p * n * whole)


def largest_part_3d(p, whole=WHOLE_BYTES_3D):
    """The most particles a rank's part can have on p ranks within MEM_PER_RANK."""
    return (MEM_PER_RANK - FIXED_BYTES_3D) / max(PART_BYTES_3D, SETUP_PART_BYTES_3D + p * whole)


def output_times_3d(p, n):
    """(the snapshot gathered to rank 0, written collectively with MPI-IO) in s: the gather
    funnels P n particles through rank 0's link; MPI-IO writes each rank's rows in parallel
    up to the file system's aggregate bandwidth."""
    total = p * n * SNAP_BYTES_3D
    return total / BANDWIDTH, total / min(p * BANDWIDTH, FS_BANDWIDTH)


def mesh_read_time_3d(p, n, indexed=True):
    """A mesh file's reading at the set-up (s) on p ranks of n nodes each, at a rank's own
    bandwidth until the file system's aggregate is shared: with the index, each rank its
    part (MESH_READ_PART_BYTES_3D a node of it); without, every rank streams the whole file
    (MESH_READ_BYTES_3D a node of the whole mesh)."""
    read = n * MESH_READ_PART_BYTES_3D if indexed else p * n * MESH_READ_BYTES_3D
    return read / min(RANK_READ_BANDWIDTH, FS_BANDWIDTH / p)


def full(p, eff):
    """The efficiency against one rank alone on its node when the nodes are full of ranks
    (from RANKS_PER_NODE ranks on): the communication model's times the measured share."""
    return f"{NODE_SHARE_3D * eff:.0f}%" if p >= RANKS_PER_NODE else "-"


def main_3d(out):
    """The 3D model: a table for 10^5 and 10^6 particles per rank, 1 to 1,024 ranks, and
    its figure (efficiency of the steps, the share of the snapshots' output, and the
    set-up's memory per rank against MEM_PER_RANK)."""
    ranks = [2 ** k for k in range(0, 11)]
    plt.rcParams.update(figure_style(savefig_dpi=120))
    fig, axs = plt.subplots(1, 2, figsize=(10.0, 4.0))
    for n, mk in ((1.0e5, "o"), (1.0e6, "s")):
        print(f"\n3D, {n:.0e} particles per rank")
        print("| ranks | step (ms) | halos + reductions (ms) | efficiency | with full "
              "nodes | snapshot, gather (s) | snapshot, MPI-IO (s) | output share, gather | "
              "peak memory per rank, part + whole body (GiB) | rank 0's gathered snapshot "
              "(GiB) | set-up, whole-body share (s) | a mesh file without its index, read "
              "whole by every rank (s) | with its index, each rank its part (s) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        eff, share_g, share_io, mem = [], [], [], []
        for p in ranks:
            w, c = step_times_3d(p, n)
            g, io = output_times_3d(p, n)
            per = STEPS_PER_SNAPSHOT * (w + c)
            eff.append(100 * w / (w + c))
            share_g.append(100 * g / (per + g))
            share_io.append(100 * io / (per + io))
            mem.append(peak_bytes_3d(p, n) / 2 ** 30)
            print(f"| {p} | {1e3 * w:.0f} | {1e3 * c:.3f} | {eff[-1]:.2f}% | "
                  f"{full(p, eff[-1])} | {g:.2f} | "
                  f"{io:.3f} | {share_g[-1]:.1f}% | {mem[-1]:.1f} | "
                  f"{p * n * SNAP_BYTES_3D / 2 ** 30:.2f} | {p * n * SETUP_WHOLE_S_3D:.0f} | "
                  f"{mesh_read_time_3d(p, n, indexed=False):.0f} | "
                  f"{mesh_read_time_3d(p, n):.2f} |")
        lab = f"{n:.0e} particles per rank"
        axs[0].semilogx(ranks, eff, mk + "-", base=2, label=f"steps, {lab}")
        axs[0].semilogx(ranks, [100 - x for x in share_g], mk + "--", base=2,
                        label=f"with snapshots gathered to rank 0, {lab}")
        axs[0].semilogx(ranks, [100 - x for x in share_io], mk + ":", base=2,
                        label=f"with snapshots by MPI-IO, {lab}")
        big = [i for i, p in enumerate(ranks) if p >= RANKS_PER_NODE]
        axs[0].semilogx([ranks[i] for i in big], [NODE_SHARE_3D * eff[i] for i in big],
                        mk + "-.", base=2,
                        alpha=0.6, label=f"steps, nodes full of ranks (x{NODE_SHARE_3D}), {lab}")
        axs[1].loglog(ranks, mem, mk + "-", base=2, label=f"peak per rank, {lab}")
        axs[1].loglog(ranks, [peak_bytes_3d(1, n) / 2 ** 30] * len(ranks), mk + ":", base=2,
                      label=f"the part's own, {lab}")
        axs[1].loglog(ranks, [p * n * SNAP_BYTES_3D / 2 ** 30 for p in ranks], mk + "--",
                      base=2, label=f"rank 0's gathered snapshot, {lab}")
    print(f"\n3D, the largest problem within {MEM_PER_RANK / 2 ** 30:.0f} GiB a rank: with "
          f"the whole body's {WHOLE_BYTES_3D / 1e3:.2f} kB a particle on every rank at the "
          "set-up (now), and without it (bodies, tables and solid built per part)")
    print("| ranks | particles a rank, now | whole problem, now | particles a rank, per "
          "part | whole problem, per part |")
    print("|---|---|---|---|---|")
    for p in ranks:
        a, b = largest_part_3d(p), largest_part_3d(p, 0.0)
        print(f"| {p} | {a:.3g} | {p * a:.3g} | {b:.3g} | {p * b:.3g} |")
    print("\n3D, a deforming master's or a self-contact's side at the set-up "
          f"({SIDE_SURFACE_BYTES_3D:.0f} B a facet, GiB): the whole surface every rank took "
          "until 2026-12-01, and the facets near its region now "
          f"({NEAR_REGION_FACTOR} x the most a part has, measured), for a cube "
          "(12 N^(2/3) facets of N particles) and for a body as thin as the weak bench's bar "
          f"({THIN_BAR_FACETS} a particle); the time loop keeps the part's only")
    print("| ranks | cube, 1e5 a rank, whole / near | cube, 1e6 a rank, whole / near | "
          "thin bar, 1e5 a rank, whole / near | thin bar, 1e6 a rank, whole / near |")
    print("|---|---|---|---|---|")
    for p in ranks:
        cells = []
        # (the whole surface's facets, and the most a part has: a cube's corner part three
        # faces of n^(2/3) particles, two facets each; the thin bar's surface is spread
        # along it, a part's share)
        for facets, part in ((lambda n: 12.0 * (p * n) ** (2.0 / 3.0),
                              lambda n: 6.0 * n ** (2.0 / 3.0)),
                             (lambda n: THIN_BAR_FACETS * p * n,
                              lambda n: THIN_BAR_FACETS * n)):
            for n in (1.0e5, 1.0e6):
                whole = facets(n) * SIDE_SURFACE_BYTES_3D / 2 ** 30
                near = min(whole, NEAR_REGION_FACTOR * max(part(n) * SIDE_SURFACE_BYTES_3D
                                                           / 2 ** 30, whole / p))
                cells.append(f"{whole:.3g} / {near:.3g}")
        print(f"| {p} | " + " | ".join(cells) + " |")
    axs[0].plot([2], [100 * MEASURED_3D], "^", ms=9,
                label="measured, 2 ranks (3D Taylor quarter, 37,467 particles per rank)")
    axs[0].plot(list(MEASURED_WEAK_16), [100 * e for e in MEASURED_WEAK_16.values()], "kv",
                ms=7, label="measured, 1-16 ranks of one 16-core socket (18,700 per rank)")
    axs[1].axhline(MEM_PER_RANK / 2 ** 30, color="k", lw=1.0,
                   label=f"memory per rank ({MEM_PER_RANK / 2 ** 30:.0f} GiB, assumed)")
    axs[0].set_xlabel("MPI ranks")
    axs[0].set_ylabel("efficiency (%)")
    axs[0].set_ylim(15, 102)
    axs[0].grid(True, which="both", alpha=0.3)
    axs[0].legend(loc="lower right", fontsize=6)
    axs[0].set_title(f"3D weak scaling; a snapshot every {STEPS_PER_SNAPSHOT} steps", fontsize=9)
    axs[1].set_xlabel("MPI ranks")
    axs[1].set_ylabel("memory per rank (GiB)")
    axs[1].grid(True, which="both", alpha=0.3)
    axs[1].legend(loc="upper left", fontsize=7)
    axs[1].set_title("what breaks first: the whole body at every rank's set-up", fontsize=9)
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {os.path.normpath(out)}")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--3d":
        main_3d(sys.argv[2] if len(sys.argv) > 2 else os.path.join(
            os.path.dirname(os.path.abspath(__file__)), "..", "doc", "figures",
            "mpi_scaling_model_3d.png"))
        return
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "doc", "figures",
        "mpi_scaling_model.png")
    ranks = [2 ** k for k in range(0, 11)]
    plt.rcParams.update(figure_style(savefig_dpi=120))
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    print("| ranks | work (ms) | comm, rigid master (ms) | efficiency | comm, deforming "
          "master (ms) | efficiency |")
    print("|---|---|---|---|---|---|")
    eff = {False: [], True: []}
    for p in ranks:
        row = [str(p)]
        for contact in (False, True):
            w, c = step_times(p, contact)
            eff[contact].append(w / (w + c))
            if not contact:
                row.append(f"{1e3 * w:.1f}")
            row += [f"{1e3 * c:.3f}", f"{100 * w / (w + c):.1f}%"]
        print("| " + " | ".join(row) + " |")
    ax.semilogx(ranks, [100 * e for e in eff[False]], "o-", base=2,
                label="model, rigid master")
    ax.semilogx(ranks, [100 * e for e in eff[True]], "s-", base=2,
                label="model, deforming master (ghost master particles)")
    for (name, e), m in zip(MEASURED.items(), ("^", "v")):
        ax.plot([2], [100 * e], m, ms=9, label=f"measured, 2 ranks: {name}")
    ax.set_xlabel("MPI ranks (10$^5$ nodes each)")
    ax.set_ylabel("weak-scaling efficiency (%)")
    ax.set_ylim(90, 103)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower left")
    ax.set_title(f"latency {LATENCY * 1e6:.0f} us, bandwidth {BANDWIDTH / 1e9:.0f} GB/s "
                 "(assumed); work and bytes measured")
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {os.path.normpath(out)}")


if __name__ == "__main__":
    main()
