#!/usr/bin/env python3
"""Two mfcd programs timed in alternating pairs on the same decks (a refactor that must cost
nothing: issue 21). For each deck, N rounds of (A, B) or (B, A) alternately, each run's
"time loop" seconds from its summary line (with --setup: its "set-up" seconds, the run cut
to one step by max_steps); prints each pair and the ratio B/A of the medians. Machines
differ (4x between two 2-core guests here), so only same-run ratios mean
something: run on an otherwise idle machine, and record the CPU model with the figures.

Usage: python bench/ab_time.py [--rounds 3] [--threads 1] [--setup] A_MFCD B_MFCD DECK [DECK ...]
(the decks' outputs are redirected to a temporary directory)
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def time_loop(prog, deck, work, tag, threads, setup=False):
    text = open(deck).read()
    out = os.path.join(work, tag + ".h5")
    text = re.sub(r"(?m)^(\s*file\s*=\s*)'output/[^']*'", rf"\1'{out}'", text)
    if setup:
        # one step: the set-up is what is timed
        text, n = re.subn(r"(?mi)^(\s*&solver\b)", r"\1\n  max_steps = 1", text, count=1)
        if n == 0:
            text += "\n&solver\n  max_steps = 1\n/\n"
    path = os.path.join(work, tag + ".nml")
    with open(path, "w") as f:
        f.write(text)
    p = subprocess.run([prog, path], cwd=ROOT, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    if p.returncode != 0:
        raise RuntimeError(f"{prog} {deck}: exit {p.returncode}\n{p.stderr[-1000:]}")
    if setup:
        m = re.search(r"\(set-up\s+([0-9.]+) s\)", p.stdout)
    else:
        m = re.search(r"summary: time loop\s+([0-9.]+) s", p.stdout)
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--setup", action="store_true",
                    help="time the set-up (the summary's set-up seconds; one step run)")
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("decks", nargs="+")
    args = ap.parse_args()
    cpu = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    print(f"# {os.cpu_count()} cores, {cpu}; {args.threads} thread(s); A = {args.a}; "
          f"B = {args.b}; timed: {'set-up' if args.setup else 'time loop'}")
    with tempfile.TemporaryDirectory(prefix="mfcd_ab_") as work:
        for deck in args.decks:
            ta, tb = [], []
            for k in range(args.rounds):
                order = [("a", args.a, ta), ("b", args.b, tb)]
                if k % 2:
                    order.reverse()
                for tag, prog, acc in order:
                    acc.append(time_loop(prog, os.path.abspath(deck), work, tag, args.threads,
                                         args.setup))
                print(f"{os.path.basename(deck)} round {k + 1}: A {ta[-1]:.3f} s, "
                      f"B {tb[-1]:.3f} s", flush=True)
            ma, mb = statistics.median(ta), statistics.median(tb)
            print(f"{os.path.basename(deck)}: median A {ma:.3f} s, B {mb:.3f} s, "
                  f"B/A {mb / ma:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
