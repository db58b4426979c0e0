#!/usr/bin/env python3
"""Input that can never hurt, and a line-buffered log (issue 8, items 4 and 8).

What mfcd writes and what it never touches (doc/deck.md): no shell ever sees a path from
the deck; the output never lands on the deck, its XDMF companion or a particle file; no
file of the user's is touched (the old '<output>.probe' is gone); a bad deck creates
nothing, not even the output directory; overwrite = .false. refuses before anything is
written; overwrite must be a logical; a run writes under temporary names and renames on
completion, so a failed run leaves an earlier result byte-identical and its own files under
<stem>.failed.h5 and <stem>.failed.xdmf, and a good run leaves no temporary file. The log
reaches a pipe line by line, the error follows the log lines it ends, and the last line
says how the run ended.
Standard library only.
Usage: test_file_safety.py /path/to/mfcd /path/to/input/elastic_wave.nml
"""
import hashlib
import os
import re
import select
import subprocess
import sys
import tempfile
import time

MFCD = os.path.abspath(sys.argv[1])
WAVE = open(os.path.abspath(sys.argv[2])).read()
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "file_safety." + name
          + ("" if cond else ": " + str(detail)[-800:]))


def run(args, cwd, timeout=300):
    p = subprocess.run([MFCD] + args, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def detect_deck(output, extra="", body=None):
    """A small 'detect' deck (a fraction of a second)."""
    body = body or ("  shape = 'rectangle'\n  lo = 0.0, 0.0\n  hi = 1.0, 1.0\n"
                    "  n = 11, 11\n")
    return ("&run ndim = 2 /\n&body\n  name = 'block'\n" + body + "/\n"
            "&detection\n  grid_lo = -0.5, -0.5\n  grid_hi = 1.5, 1.5\n  grid_n = 21, 21\n/\n"
            f"&output file = '{output}'{extra} /\n")


def wave_deck(output, unstable=False, t_end=None, extra=""):
    """The elastic-wave deck; unstable: a fixed dt five times the critical one (it fails
    at step 3, as tests/regression/check_guards.py provokes it)."""
    text = WAVE.replace("output/elastic_wave.h5", output)
    if unstable:
        text = re.sub(r"cfl = 0\.5", "dt = 7.0e-7", text)
    if t_end:
        text = re.sub(r"t_end = [0-9.eE+-]+", f"t_end = {t_end}", text)
    if extra:
        text = text.replace(f"file = '{output}'", f"file = '{output}'{extra}")
    return text


def case_dir(root, name):
    d = os.path.join(root, name)
    os.makedirs(d)
    return d


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def tree(d):
    """Every entry under d with its kind, size, mtime (ns) and content hash."""
    out = {}
    for base, dirs, files in os.walk(d):
        for n in dirs + files:
            p = os.path.join(base, n)
            st = os.lstat(p)
            h = digest(p) if os.path.isfile(p) and not os.path.islink(p) else None
            out[os.path.relpath(p, d)] = (st.st_mode, st.st_size, st.st_mtime_ns, h)
    return out


def listing(d):
    return sorted(os.listdir(d)) if os.path.isdir(d) else []


def temp_files(d):
    return [n for n in (os.listdir(d) if os.path.isdir(d) else []) if ".tmp-" in n]


def shell_injection(root):
    """A path with shell syntax is just a name: no command runs, the file is made there."""
    d = case_dir(root, "inject")
    out = "out/x$(touch y)`touch z`;touch w/run.h5"
    deck = write(os.path.join(d, "deck.nml"), detect_deck(out))
    rc, so, se = run([deck], d)
    check("shell injection: the run works literally", rc == 0 and os.path.isfile(
        os.path.join(d, out)), (rc, se, os.listdir(d)))
    made = [p for p in ("y", "z", "w", "out/y", "out/z", "out/w") if os.path.exists(
        os.path.join(d, p))]
    check("shell injection: no command ran (no file y, z or w)", not made, made)
    where = os.path.dirname(os.path.join(d, out))
    check("shell injection: no temporary file left", not temp_files(where), listing(where))


def output_is_the_deck(root):
    """The output is the deck under another spelling: refused, the deck untouched."""
    d = case_dir(root, "deck_itself")
    os.symlink(".", os.path.join(d, "here"))
    for spelling in ("./deck.nml", "here/deck.nml", "../deck_itself/deck.nml"):
        deck = write(os.path.join(d, "deck.nml"), detect_deck(spelling))
        before = tree(d)
        rc, so, se = run([deck], d)
        check(f"output '{spelling}' = the deck: exit 2 naming &output file and the deck",
              rc == 2 and "&output" in se and "file" in se and "the deck itself" in se,
              (rc, se))
        check(f"output '{spelling}' = the deck: deck and directory untouched",
              tree(d) == before)
    # the XDMF companion of output 'case.h5' is 'case.xdmf': the deck when so named
    deck = write(os.path.join(d, "case.xdmf"), wave_deck("case.h5"))
    before = tree(d)
    rc, so, se = run([deck], d)
    check("XDMF companion = the deck: exit 2, nothing touched",
          rc == 2 and "the deck itself" in se and tree(d) == before, (rc, se))
    # a particle file of the deck is an input too
    pts = []
    for j in range(11):
        for i in range(11):
            pts.append((0.1 * i, 0.1 * j))
    ring = ([(i, 0) for i in range(10)] + [(10, j) for j in range(10)]
            + [(i, 10) for i in range(10, 0, -1)] + [(0, j) for j in range(10, 0, -1)])
    order = {ij: k + 1 for k, ij in enumerate(ring)}
    with open(os.path.join(d, "pts.txt"), "w") as f:
        for j in range(11):
            for i in range(11):
                k = order.get((i, j), 0)
                f.write(f"{0.1 * i:.3f} {0.1 * j:.3f} 0.01 {1 if k else 0} {k}\n")
    body = "  shape = 'file'\n  file = 'pts.txt'\n  spacing = 0.1, 0.1\n"
    deck = write(os.path.join(d, "pfile.nml"), detect_deck("pts.txt", body=body))
    before = tree(d)
    rc, so, se = run([deck], d)
    check("output = the deck's particle file: exit 2 naming it, nothing touched",
          rc == 2 and "particle file" in se and "block" in se and tree(d) == before, (rc, se))


def old_probe_name(root):
    """A user's file named like the old writability probe '<output>.probe' is untouched."""
    d = case_dir(root, "probe")
    os.makedirs(os.path.join(d, "out"))
    probe = write(os.path.join(d, "out", "run.h5.probe"), "the user's own notes\n")
    st = os.stat(probe)
    deck = write(os.path.join(d, "deck.nml"), detect_deck("out/run.h5"))
    rc, so, se = run([deck], d)
    check("user file 'run.h5.probe': run works", rc == 0, se)
    check("user file 'run.h5.probe': byte-identical, same mtime", os.path.isfile(probe) and
          open(probe).read() == "the user's own notes\n" and
          st.st_mtime_ns == os.stat(probe).st_mtime_ns)
    names = listing(os.path.join(d, "out"))
    check("only the result and the user's file in the directory",
          names == ["run.h5", "run.h5.probe"], names)


def bad_deck_creates_nothing(root):
    """Bad input with a missing output directory: exit 2, and the tree is as it was."""
    d = case_dir(root, "bad_nothing")
    write(os.path.join(d, "bad.txt"), "1.0 2.0\nnot a number here\n")
    cases = {
        "deck error": detect_deck("new/sub/run.h5").replace(
            "  n = 11, 11\n", "  n = 11, 11\n  kernel = 'spline'\n"),
        "overwrite error": detect_deck("new/sub/run.h5", ", overwrite = 'no'"),
        "body error": detect_deck("new/sub/run.h5",
                                  body="  shape = 'file'\n  file = 'bad.txt'\n"),
        "dynamic set-up error": wave_deck("new/sub/run.h5").replace(
            "material = 'steel_elastic'\n/\n&bc", "material = 'steel_elastic'\n"
            "  role = 'rigid'\n/\n&bc"),
    }
    for what, text in cases.items():
        deck = write(os.path.join(d, "deck.nml"), text)
        before = tree(d)
        time.sleep(0.01)
        rc, so, se = run([deck], d)
        check(f"bad input ({what}), missing output directory: exit 2", rc == 2, (rc, se))
        check(f"bad input ({what}): no directory, no file, nothing changed",
              tree(d) == before and not os.path.exists(os.path.join(d, "new")),
              sorted(tree(d)))


def overwrite_false(root):
    """overwrite = .false. with an earlier result: exit 2 before anything is written."""
    d = case_dir(root, "keep")
    deck = write(os.path.join(d, "deck.nml"), detect_deck("out/run.h5"))
    rc, so, se = run([deck], d)
    check("first run writes the result", rc == 0 and os.path.isfile(
        os.path.join(d, "out", "run.h5")), se)
    for spelling in (".false.", "F", "f", "false"):
        write(deck, detect_deck("out/run.h5", f", overwrite = {spelling}"))
        before = tree(d)
        rc, so, se = run([deck], d)
        check(f"overwrite = {spelling} with a result: exit 2 naming overwrite and the file",
              rc == 2 and "overwrite = .false." in se and "out/run.h5" in se, (rc, se))
        check(f"overwrite = {spelling}: the old result byte-identical, nothing written",
              tree(d) == before)
    # the failed-run name is one of the names a run may write: also kept
    os.rename(os.path.join(d, "out", "run.h5"), os.path.join(d, "out", "run.failed.h5"))
    write(deck, detect_deck("out/run.h5", ", overwrite = .false."))
    before = tree(d)
    rc, so, se = run([deck], d)
    check("overwrite = .false. with an old run.failed.h5: exit 2 naming it, untouched",
          rc == 2 and "run.failed.h5" in se and tree(d) == before, (rc, se))


def overwrite_not_logical(root):
    """overwrite = 'no' (and other non-logicals): exit 2 naming &output, overwrite, the fix."""
    d = case_dir(root, "notlogical")
    for value in ("'no'", "'false'", "'F'", '".true."', "no", "yes", "0", "1"):
        deck = write(os.path.join(d, "deck.nml"), detect_deck("out/run.h5",
                                                              f", overwrite = {value}"))
        rc, so, se = run([deck], d)
        check(f"overwrite = {value}: exit 2 naming &output, overwrite and the fix",
              rc == 2 and "&output" in se and "overwrite" in se and
              ".true. or .false." in se and se.count("mfcd: error:") == 1, (rc, se))
    check("overwrite not a logical: nothing written", not os.path.exists(
        os.path.join(d, "out")))
    for value in (".true.", "T", "t", "true", ".false.", "F"):
        deck = write(os.path.join(d, "deck.nml"), detect_deck("out/run.h5",
                                                              f", overwrite = {value}"))
        rc, so, se = run(["--check", deck], d)
        check(f"overwrite = {value} is a logical", rc == 0, (rc, se))


def failed_run_keeps_result(root):
    """A run that goes unstable leaves the earlier good result byte-identical and writes
    its own files under the failed-run names; a good run leaves no temporary file."""
    d = case_dir(root, "failed")
    out = os.path.join(d, "out")
    good = write(os.path.join(d, "good.nml"), wave_deck("out/wave.h5"))
    rc, so, se = run([good], d)
    check("good dynamic run: exit 0", rc == 0, se)
    check("good dynamic run: the result and its XDMF, no temporary file",
          listing(out) == ["wave.h5", "wave.xdmf"], listing(out))
    xdmf = open(os.path.join(out, "wave.xdmf")).read()
    refs = set(re.findall(r">([^<>:]+):/", xdmf))
    check("the XDMF file names the HDF5 file by its final relative name",
          refs == {"wave.h5"}, refs)
    check("good run: last line says completed and names the files",
          so.strip().splitlines()[-1] == "mfcd: completed: wrote out/wave.h5 and out/wave.xdmf",
          so[-300:])
    before = {n: (digest(os.path.join(out, n)), os.stat(os.path.join(out, n)).st_mtime_ns)
              for n in os.listdir(out)}
    bad = write(os.path.join(d, "bad.nml"), wave_deck("out/wave.h5", unstable=True))
    # stdout and stderr into one file, as 'mfcd deck > log 2>&1' does
    with open(os.path.join(d, "combined.txt"), "w") as f:
        rc = subprocess.run([MFCD, bad], cwd=d, stdout=f, stderr=subprocess.STDOUT,
                            timeout=300).returncode
    combined = open(os.path.join(d, "combined.txt")).read()
    check("unstable run: exit 1", rc == 1, combined[-500:])
    after = {n: (digest(os.path.join(out, n)), os.stat(os.path.join(out, n)).st_mtime_ns)
             for n in ("wave.h5", "wave.xdmf") if os.path.isfile(os.path.join(out, n))}
    check("unstable run: the earlier result and its XDMF byte-identical, same mtime",
          after == before, (before, after))
    names = listing(out)
    check("unstable run: its files under the failed-run names, no temporary file",
          names == ["wave.failed.h5", "wave.failed.xdmf", "wave.h5", "wave.xdmf"], names)
    if os.path.exists(os.path.join(out, "wave.failed.xdmf")):
        refs = set(re.findall(r">([^<>:]+):/", open(os.path.join(out,
                                                                 "wave.failed.xdmf")).read()))
        check("the failed run's XDMF names its own HDF5 file", refs == {"wave.failed.h5"},
              refs)
    lines = combined.strip().splitlines()
    i_fail = next((i for i, l in enumerate(lines) if l.startswith("dynamic: FAILED")), -1)
    i_sum = max((i for i, l in enumerate(lines) if l.startswith("summary:")), default=-1)
    i_err = next((i for i, l in enumerate(lines) if l.startswith("mfcd: error:")), -1)
    check("stdout and stderr in one file: the error comes after the log lines it follows",
          0 <= i_fail < i_sum < i_err, (i_fail, i_sum, i_err, lines[-6:]))
    err_line = lines[i_err] if i_err >= 0 else ""
    check("the error line: the reason, the failed files, the kept result",
          err_line.startswith("mfcd: error: run failed at step") and
          "out/wave.failed.h5" in err_line and "out/wave.h5 is untouched" in err_line,
          err_line)
    # one file for both streams: the message once (issue 22: every error was printed twice),
    # the last line saying how the run ended and pointing at it
    check("last line: failed (exit 1), pointing at the error above, not repeating it",
          lines[-1] == "mfcd: failed (exit 1) (the error above)" and
          sum("run failed at step" in ln for ln in lines) == 1, lines[-2:])
    # a second good run replaces the result (overwrite = .true., the default) and leaves
    # no temporary file either
    rc, so, se = run([good], d)
    check("good run again: exit 0, no temporary file", rc == 0 and not temp_files(out),
          (se, listing(out)))


def log_is_line_buffered(root):
    """The first log line reaches a pipe, and a file, while mfcd still runs: a run of the
    elastic wave to 1000 times its end time (minutes), killed once the line is seen.
    gfortran buffers unit 6 when it is a regular file, so without a flush after each line
    the file stays empty until the program ends (a pipe it leaves alone). (A FIFO as the
    deck once held mfcd at its first read; a deck is now read as a plain file only.)"""
    d = case_dir(root, "pipe")
    long_run = write(os.path.join(d, "deck.nml"), wave_deck("out/long.h5", t_end="1.0e-2"))
    p = subprocess.Popen([MFCD, long_run], cwd=d, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE)
    try:
        ready, _, _ = select.select([p.stdout], [], [], 30.0)
        first = p.stdout.readline().decode() if ready else ""
        alive = p.poll() is None
        check("log to a pipe: the first line arrives while the program still runs",
              bool(ready) and first.startswith("mfcd ") and alive, (first, alive))
    finally:
        p.kill()
        p.wait()
    log = os.path.join(d, "log.txt")
    with open(log, "w") as f:
        p = subprocess.Popen([MFCD, long_run], cwd=d, stdout=f, stderr=subprocess.DEVNULL)
    try:
        t0 = time.time()
        while os.path.getsize(log) == 0 and time.time() - t0 < 20.0:
            time.sleep(0.05)
        first = open(log).read()
        alive = p.poll() is None
        check("log to a file: the first line is in the file while the program still runs",
              first.startswith("mfcd ") and alive, (first, alive))
    finally:
        p.kill()
        p.wait()
    # a short run read as it goes: the deck echo comes before the program ends
    deck = write(os.path.join(d, "wave.nml"), wave_deck("out/wave.h5"))
    p = subprocess.Popen([MFCD, deck], cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    lines = [l.rstrip("\n") for l in p.stdout]
    p.wait()
    check("short run: exit 0, last line says completed", p.returncode == 0 and lines and
          lines[-1].startswith("mfcd: completed:"), lines[-3:])
    check("short run: the log names the temporary files and the final names",
          any(l.startswith("output: writing out/.wave.h5.tmp-") and "out/wave.h5" in l
              for l in lines), [l for l in lines if l.startswith("output:")])


def bad_input_last_line(root):
    """Bad input: the error on stderr, and the log's last line says so."""
    d = case_dir(root, "lastline")
    deck = write(os.path.join(d, "deck.nml"), detect_deck("out/run.h5").replace(
        "  n = 11, 11\n", "  n = 11, 11\n  kernel = 'spline'\n"))
    rc, so, se = run([deck], d)
    check("bad input: last log line says bad input (exit 2), nothing written",
          rc == 2 and so.strip().splitlines()[-1].startswith(
              "mfcd: bad input (exit 2), nothing written: deck"), so[-300:])


def main():
    root = tempfile.mkdtemp(prefix="mfcd_files_")
    shell_injection(root)
    output_is_the_deck(root)
    old_probe_name(root)
    bad_deck_creates_nothing(root)
    overwrite_false(root)
    overwrite_not_logical(root)
    failed_run_keeps_result(root)
    log_is_line_buffered(root)
    bad_input_last_line(root)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
