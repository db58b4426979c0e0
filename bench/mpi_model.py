#!/usr/bin/env python3
"""The communication model of doc/parallel.md drawn: weak-scaling efficiency of mfcd_mpi
against the number of ranks, for 10^5 nodes per rank (10^8 at 10^3 ranks), from the counts
measured on this machine, with the measured 2-rank points beside it.

    .venv/bin/python bench/mpi_model.py [OUT.png]   (default doc/figures/mpi_scaling_model.png)

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


def main():
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
