"""What every benchmark result of record carries (doc/benchmarks.md: date, commit, machine,
load, command), in one place for the bench/ scripts.

    from bench_record import sh, record_head, write_results
    head = record_head("# Title (bench/x.py)", "python3 bench/x.py --rounds 3")
    ...
    head.append(load_row("after"))
    write_results("x", head + lines)     # bench/results/x_<date>.md (git-ignored)
"""
import datetime
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# post/mfcd_h5.py, the reader of mfcd's output files, for every bench script
sys.path.insert(0, os.path.join(ROOT, "post"))


def sh(cmd):
    """A shell command's standard output, stripped, run in the repository root."""
    return subprocess.run(cmd, shell=True, capture_output=True, text=True,
                          cwd=ROOT).stdout.strip()


def cpu_text():
    """The CPU model (lscpu) and the core count."""
    return "%s, %s cores" % (sh("lscpu | sed -n 's/^Model name: *//p'"), os.cpu_count())


def load_row(when):
    """A Markdown row with the load average now ('before' or 'after')."""
    return "| load %s | %s |" % (when, sh("cat /proc/loadavg"))


def record_head(title, command, extra_rows=()):
    """The title and a Markdown table of date (UTC), commit, CPU, load before, any extra
    rows (already formatted) and the command."""
    now = datetime.datetime.now(datetime.timezone.utc)
    dirty = " (dirty)" if sh("git status --porcelain -uno") else ""
    return [title, "", "| | |", "|---|---|",
            "| date | %s |" % now.strftime("%Y-%m-%d %H:%M UTC"),
            "| commit | `%s`%s |" % (sh("git rev-parse --short HEAD"), dirty),
            "| CPU | %s |" % cpu_text(),
            load_row("before")] + list(extra_rows) + ["| command | `%s` |" % command]


def write_results(name, lines, suffix=".md"):
    """lines into bench/results/<name>_<date><suffix>; returns the path."""
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d_%H%M%S")
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    path = os.path.join(ROOT, "bench", "results", "%s_%s%s" % (name, stamp, suffix))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path
