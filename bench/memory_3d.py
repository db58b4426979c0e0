#!/usr/bin/env python3
"""Peak resident memory of 3D RKPM runs, bytes per particle and the largest 3D body that
fits this machine (the 3D counterpart of bench/memory.py).

    .venv/bin/python bench/memory_3d.py [--sides 21,31,46] [--steps 10] [--build-dir build]

Runs the 3D benchmark deck (bench/decks/bar_3d_elastic_bench.nml: an elastic steel 'box',
RKPM, basis 'linear', SCNI over prism cells with the sub-cell stabilization, support_factor
2.0) as cubes of n x n x n particles (--sides; the default 21, 31, 46 gives 9,261, 29,791 and
97,336 particles), each stopped after --steps steps (&solver max_steps; the time loop
allocates nothing, so the set-up holds the peak), 1 thread. Three numbers per run:

- the peak resident set size of the whole run, ru_maxrss from wait4(2), as bench/memory.py;
- the set-up's peak: VmHWM of /proc/<pid>/status when the log prints the time loop's first
  energy row (cycle 0), polled every --poll seconds;
- the time loop's resident size: the largest VmRSS polled after that row. The set-up's work
  arrays (candidate lists, the moment and shape-function scratch) are freed by then; what
  stays is the tables the loop reads.

Reports MiB, bytes per particle and per point-node entry, the set-up's own estimate (the
log's 'memory:' line), the slope between sizes (bytes per extra particle), and from the two
largest runs the largest cube whose set-up peak fits the machine's memory (MemTotal of
/proc/meminfo; less in practice: other processes, the page cache) and whether 10^6 particles
fit. Prints Markdown and writes bench/results/memory_3d_<date>.md (git-ignored).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import threading
import time

from bench_record import ROOT, load_row, record_head, write_results

DECK = os.path.join(ROOT, "bench", "decks", "bar_3d_elastic_bench.nml")
DX = 0.25e-3                           # the deck's spacing; the cube's side is (n - 1) dx


def meminfo(key):
    """A /proc/meminfo entry in bytes."""
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


def proc_kb(pid, key):
    """VmRSS or VmHWM of a process in kB (0 once it has gone)."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def deck_text(n, steps, out):
    side = (n - 1) * DX
    text = open(DECK).read()
    text = re.sub(r"file\s*=\s*'[^']*'", "file = '%s'" % out, text)
    text = re.sub(r"\bn\s*=\s*\d+\s*,\s*\d+\s*,\s*\d+", "n = %d, %d, %d" % (n, n, n), text)
    text = re.sub(r"\bhi\s*=\s*[^\n]*", "hi = %r, %r, %r" % (side, side, side), text)
    # an energy row every step (the poller's marker); no snapshot (t_end is not reached)
    text = re.sub(r"log_every\s*=\s*\d+", "log_every = 1", text)
    text = re.sub(r"(&solver\b[^\n]*\n)", r"\1  max_steps = %d\n" % steps, text, count=1)
    return text


def run(mfcd, n, steps, tmp, poll):
    out = os.path.join(tmp, "cube%d.h5" % n)
    deck = os.path.join(tmp, "cube%d.nml" % n)
    open(deck, "w").write(deck_text(n, steps, out))
    logpath = os.path.join(tmp, "cube%d.log" % n)
    log = open(logpath, "w")
    t0 = time.perf_counter()
    p = subprocess.Popen([mfcd, deck], stdout=log, stderr=subprocess.STDOUT, cwd=tmp,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    state = {"setup_hwm": 0, "loop_rss": 0, "t_loop": None}
    done = threading.Event()

    def poller():
        marker = re.compile(r"^dynamic:\s+0\s", re.M)
        while not done.is_set():
            rss, hwm = proc_kb(p.pid, "VmRSS"), proc_kb(p.pid, "VmHWM")
            if state["t_loop"] is None:
                with open(logpath) as f:
                    if marker.search(f.read()):
                        state["t_loop"] = time.perf_counter() - t0
                        state["setup_hwm"] = hwm
                        continue
            else:
                state["loop_rss"] = max(state["loop_rss"], rss)
            time.sleep(poll)

    th = threading.Thread(target=poller)
    th.start()
    _, status, ru = os.wait4(p.pid, 0)
    done.set()
    th.join()
    log.close()
    text = open(logpath).read()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("run failed: %s\n%s" % (deck, text[-2000:]))
    m = re.search(r"dynamic: body '[^']*': ([0-9]+) nodes, ([0-9]+) integration points.*?"
                  r"([0-9]+) point-node entries \(mean ([0-9]+) nodes per point\)", text)
    est = re.search(r"memory: about ([0-9.]+) (kB|MB|GB) estimated", text)
    est_mib = None
    if est:
        est_mib = float(est.group(1)) * {"kB": 1e3, "MB": 1e6, "GB": 1e9}[est.group(2)] \
            / 1048576.0
    setup = re.search(r"set-up\s+([0-9.]+) s", text)
    return {"n": n, "np": int(m.group(1)), "entries": int(m.group(3)),
            "mean": int(m.group(4)), "peak": ru.ru_maxrss / 1024.0,
            "setup_peak": state["setup_hwm"] / 1024.0, "loop": state["loop_rss"] / 1024.0,
            "est": est_mib, "setup_s": float(setup.group(1)) if setup else float("nan"),
            "wall": time.perf_counter() - t0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sides", default="21,31,46",
                    help="cube sides in particles (default 21,31,46)")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--poll", type=float, default=0.02, help="seconds between RSS polls")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    mfcd = os.path.join(os.path.abspath(a.build_dir), "bin", "mfcd")
    if not os.access(mfcd, os.X_OK):
        sys.exit("no %s: build it first (bash tools/build.sh Release build)" % mfcd)
    total = meminfo("MemTotal")
    cmd = ".venv/bin/python bench/memory_3d.py --sides %s --steps %d%s" % (
        a.sides, a.steps, "" if os.path.abspath(a.build_dir) == os.path.join(ROOT, "build")
        else " --build-dir %s" % os.path.relpath(os.path.abspath(a.build_dir), ROOT))
    lines = record_head("# Peak memory in 3D (bench/memory_3d.py)", cmd, [
        "| memory | MemTotal %.1f GiB, MemAvailable %.1f GiB |" % (
            total / 2.0 ** 30, meminfo("MemAvailable") / 2.0 ** 30)]) + ["",
        "| cube | particles | point-node entries (mean per point) | set-up (s) | "
        "peak RSS (MiB) | set-up's peak (MiB) | time loop RSS (MiB) | set-up's estimate (MiB) "
        "| bytes per particle (peak) | bytes per particle (loop) | bytes per entry (peak) |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(s) for s in a.sides.split(",")):
            r = run(mfcd, n, a.steps, tmp, a.poll)
            rows.append(r)
            row = ("| %d^3 | %d | %d (%d) | %.1f | %.1f | %.1f | %.1f | %s | %.0f | %.0f "
                   "| %.0f |") % (
                n, r["np"], r["entries"], r["mean"], r["setup_s"], r["peak"], r["setup_peak"],
                r["loop"], "%.1f" % r["est"] if r["est"] is not None else "-",
                r["peak"] * 1048576.0 / r["np"], r["loop"] * 1048576.0 / r["np"],
                r["peak"] * 1048576.0 / r["entries"])
            lines.append(row)
            print(row, flush=True)
    lines += ["", "| from -> to | particles ratio | peak RSS ratio | bytes per extra particle "
              "(peak) | (time loop) | (set-up's estimate) |", "|---|---|---|---|---|---|"]
    for r0, r1 in zip(rows, rows[1:]):
        dn = r1["np"] - r0["np"]
        lines.append("| %d^3 -> %d^3 | %.2f | %.2f | %.0f | %.0f | %s |" % (
            r0["n"], r1["n"], r1["np"] / r0["np"], r1["peak"] / r0["peak"],
            (r1["peak"] - r0["peak"]) * 1048576.0 / dn, (r1["loop"] - r0["loop"]) * 1048576.0
            / dn, "%.0f" % ((r1["est"] - r0["est"]) * 1048576.0 / dn)
            if r0["est"] is not None and r1["est"] is not None else "-"))
    if len(rows) >= 2:
        r0, r1 = rows[-2], rows[-1]
        out = [""]
        for key, what in (("peak", "the run's peak"), ("loop", "the time loop")):
            slope = (r1[key] - r0[key]) * 1048576.0 / (r1["np"] - r0["np"])
            fixed = r1[key] * 1048576.0 - slope * r1["np"]
            largest = (total - fixed) / slope
            at_1e6 = (fixed + slope * 1e6) / 2.0 ** 30
            out.append("- %s, linear through the two largest cubes: %.0f bytes per particle "
                       "+ %.0f MiB; %.3g particles fill MemTotal %.1f GiB (a cube of %d^3); "
                       "10^6 particles need %.1f GiB: %s" % (
                           what, slope, fixed / 1048576.0, largest, total / 2.0 ** 30,
                           int(largest ** (1.0 / 3.0)), at_1e6,
                           "fits" if at_1e6 * 2.0 ** 30 < total else "does not fit"))
        lines += out
    lines += ["", load_row("after")]
    print("\n".join(lines[-(len(rows) + 6):]))
    path = write_results("memory_3d", lines)
    print("written: " + os.path.relpath(path, ROOT), file=sys.stderr)


if __name__ == "__main__":
    main()
