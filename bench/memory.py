#!/usr/bin/env python3
"""Peak resident memory of mfcd runs and its growth with the particle count (issue 9,
item 8).

    .venv/bin/python bench/memory.py [--steps 40] [--full]

Runs the RKPM and FEM Taylor decks at three resolutions (coarse, the paper's, fine), each
stopped after --steps steps (&solver max_steps: the set-up builds every table and the time
loop allocates nothing, so the peak is reached by then; --full also runs the paper's RKPM
deck to the end to show it), 1 thread, and reads the peak resident set size of each run
from wait4(2) (ru_maxrss). Reports MiB, bytes per node and per integration point, the
set-up's own estimate (the log's 'memory:' line), and the slope between resolutions.
Prints Markdown and writes bench/results/memory_<date>.md (git-ignored).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

from bench_record import ROOT, record_head, sh, write_results

MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
DECKS = [("RKPM", "coarse", "taylor_bar_rkpm_coarse.nml"),
         ("RKPM", "paper", "taylor_bar_rkpm.nml"),
         ("RKPM", "fine", "taylor_bar_rkpm_fine.nml"),
         ("FEM", "coarse", "taylor_bar_fem_coarse.nml"),
         ("FEM", "paper", "taylor_bar_fem_cfl.nml"),
         ("FEM", "fine", "taylor_bar_fem_fine.nml")]


def run(deck_name, steps, tmp, tag):
    text = open(os.path.join(ROOT, "input", deck_name)).read()
    out = os.path.join(tmp, tag + ".h5")
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = '%s'" % out, text)
    if steps:
        text = re.sub(r"(&solver\b[^\n]*\n)", r"\1  max_steps = %d\n" % steps, text, count=1)
    deck = os.path.join(tmp, tag + ".nml")
    open(deck, "w").write(text)
    log = open(os.path.join(tmp, tag + ".log"), "w+")
    p = subprocess.Popen([MFCD, deck], stdout=log, stderr=subprocess.STDOUT, cwd=tmp,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    _, status, ru = os.wait4(p.pid, 0)
    log.seek(0)
    text = log.read()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("run failed: %s\n%s" % (deck, text[-2000:]))
    nodes = points = 0
    for m in re.finditer(r"dynamic: body '[^']*': ([0-9]+) nodes, ([0-9]+) integration "
                         r"points", text):
        nodes += int(m.group(1))
        points += int(m.group(2))
    est = re.search(r"memory: about ([0-9.]+) (kB|MB|GB) estimated", text)
    est_mib = None
    if est:
        scale = {"kB": 1e3, "MB": 1e6, "GB": 1e9}[est.group(2)]
        est_mib = float(est.group(1)) * scale / 1048576.0
    return ru.ru_maxrss / 1024.0, nodes, points, est_mib, text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--full", action="store_true")
    a = ap.parse_args()
    memory = "| memory | %s GiB |" % sh("free -g | awk '/Mem/{print $2}'")
    lines = record_head("# Peak memory (bench/memory.py)",
                        ".venv/bin/python bench/memory.py --steps %d%s" %
                        (a.steps, " --full" if a.full else ""), [memory]) + ["",
             "| method | resolution | nodes | points | steps | peak RSS (MiB) | "
             "set-up's estimate (MiB) | bytes per point |", "|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        runs = [(m, r, d, a.steps) for m, r, d in DECKS]
        if a.full:
            runs.append(("RKPM", "paper (whole run)", "taylor_bar_rkpm.nml", 0))
        for k, (method, res, deck, steps) in enumerate(runs):
            rss, nodes, points, est, text = run(deck, steps, tmp, "run%d" % k)
            rows.append((method, res, nodes, points, rss))
            row = "| %s | %s | %s | %s | %s | %.1f | %s | %s |" % (
                method, res, nodes or "?", points or "?", steps or "all", rss,
                "%.1f" % est if est is not None else "-",
                "%.0f" % (rss * 1048576.0 / points) if points else "?")
            lines.append(row)
            print(row, flush=True)
    # growth: slope of RSS against the point count between the resolutions of each method
    lines += ["", "| method | from -> to | points ratio | RSS ratio | MiB per 1000 points |",
              "|---|---|---|---|---|"]
    for method in ("RKPM", "FEM"):
        rs = [r for r in rows if r[0] == method and "whole" not in r[1] and r[3]]
        for r0, r1 in zip(rs, rs[1:]):
            lines.append("| %s | %s -> %s | %.2f | %.2f | %.3f |" % (
                method, r0[1], r1[1], r1[3] / r0[3], r1[4] / r0[4],
                (r1[4] - r0[4]) / ((r1[3] - r0[3]) / 1000.0)))
    print("\n".join(lines[-(2 + 2 * 2):]))
    path = write_results("memory", lines)
    print("written: " + os.path.relpath(path, ROOT), file=sys.stderr)


if __name__ == "__main__":
    main()
