#!/usr/bin/env python3
"""The hostile-script corpus (issue 20): a deck and a gmsh script from someone else can
never run a command, touch a file or hang mfcd.

Written as an attacker thinks, not from the words mfcd refuses: gmsh's command aliases,
command names built from strings, quotes and comments that would make a scanner and
gmsh's parser read different text, options and plugins that write or read files, reads of
other files, size and stream tricks, compressed and non-text bytes, process exits, hangs,
and valid scripts whose meshes outgrow their limits. Each case's payload creates a marker
file (or deletes, renames or empties the deck).

The cases: every tests/cli/hostile_geo/*.geo, whose header says what it does and what to
expect:

    // hostile (<class>): <what the script does>    (or 'limit (...)', 'contained (...)')
    // expect: <words the message must hold>        (one or more; 'line N' names the line)
    // exit: 0                                      (contained: the run goes on; default 2)
    // deck: geo_time_limit = 1, ...                (&body variables for this case)
    // requires: gmsh                               (skipped by an mfcd without gmsh)
    // within: <seconds>                            (the most a run may take; default 20)
    // ndim: 3                                      (a 3D deck: gmsh meshes tetrahedra)

and the cases made here, which need files a repository cannot hold: a FIFO with no writer,
sparse files of 2^31 and 2^32 bytes and more, a file one byte over the limit, a symbolic
link to /dev/zero, a directory, gzip-compressed, UTF-16 and NUL bytes, a name other than
*.geo (a .gz, /etc/passwd), a 1 MB script of 58,000 distinct names (read in linear time),
parentheses nested 500,000 deep, a name of 1,000 characters.

For each case, in fresh directories (the working directory holding deck.nml, case.geo,
the second script that Include and Merge would read, and a planted .petscrc and petscrc
whose options would make PETSc, linked into gmsh, write files; an empty HOME; an empty
TMPDIR; an empty directory for the markers), `mfcd --check deck.nml` and `mfcd deck.nml`
must:

- exit with code 2 (or 0 for a contained case), the message naming the deck, every
  expected word and, for a script, its line;
- end within the case's time;
- leave the working directory, HOME, TMPDIR and the marker directory exactly as they were
  (names, sizes, times, contents), but for the run's own output (out/) after a contained
  run; and, run as root, leave /etc/fltk as it was (gmsh's GUI toolkit wrote
  /etc/fltk/fltk.org/fltk.prefs whenever gmsh started).

Standard library only. Usage: test_hostile_geo.py /path/to/mfcd [case-name-substring ...]
"""
import gzip
import os
import shutil
import subprocess
import sys
import tempfile
import time

from dir_state import snapshot

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "hostile_geo")
DEFAULT_WITHIN = 20.0   # s: a refusal takes a fraction of a second
results = []

SQUARE = """Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25};
Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
"""


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "hostile_geo." + name
          + ("" if cond else ": " + str(detail)[-1500:]), flush=True)


def has_gmsh(mfcd):
    p = subprocess.run([mfcd, "--version"], capture_output=True, text=True)
    return any(line.startswith("gmsh 4") for line in p.stdout.splitlines())


def fltk_state():
    """What /etc/fltk holds (root's gmsh wrote its preferences there)."""
    if not os.path.exists("/etc/fltk"):
        return None
    return snapshot("/etc/fltk")


def header(text):
    meta = {"what": "", "expect": [], "exit": 2, "deck": "", "requires": [],
            "within": DEFAULT_WITHIN, "ndim": 2}
    for line in text.splitlines():
        if not line.startswith("//"):
            break
        body = line[2:].strip()
        if not meta["what"]:
            meta["what"] = body
        for key in ("expect", "exit", "deck", "requires", "within", "ndim"):
            if body.startswith(key + ":"):
                value = body[len(key) + 1:].strip()
                if key == "expect":
                    meta["expect"].append(value)
                elif key in ("exit", "ndim"):
                    meta[key] = int(value)
                elif key == "within":
                    meta["within"] = float(value)
                elif key == "requires":
                    meta["requires"] += value.split()
                else:
                    meta["deck"] = value
    return meta


def deck_text(geo, extra, ndim=2):
    """A detect deck (a fraction of a second once meshed) naming geo; extra: &body
    variables, 'name = value, name = value'. The time limit is 30 s unless extra says.
    ndim = 3: a 3D deck (gmsh meshes the script's volumes)."""
    body = {"geo_time_limit": "30"}
    if ndim == 3:
        body["basis"] = "'linear'"   # the default, 'bilinear', is a 2D basis
    for item in filter(None, (s.strip() for s in extra.split(","))):
        k, v = (t.strip() for t in item.split("="))
        body[k] = v
    lines = "".join(f"  {k} = {v}\n" for k, v in body.items())
    if ndim == 3:
        grid = ("  grid_lo = -0.25, -0.25, -0.25\n  grid_hi = 1.25, 1.25, 1.25\n"
                "  grid_n = 4, 4, 4\n")
    else:
        grid = "  grid_lo = -0.25, -0.25\n  grid_hi = 1.25, 1.25\n  grid_n = 4, 4\n"
    return (f"&run\n  ndim = {ndim}\n/\n&body\n  name = 'body'\n  shape = 'geo'\n"
            f"  file = '{geo}'\n{lines}/\n&detection\n{grid}/\n&output\n"
            "  file = 'out/run.h5'\n/\n")


def run_case(mfcd, name, meta, make, geo="case.geo"):
    """Run one case both ways. make(work, marks) puts the script (and anything else) in
    the working directory."""
    for check_only in (True, False):
        label = name + (" (--check)" if check_only else " (run)")
        with tempfile.TemporaryDirectory(prefix="mfcd_hostile_") as tmp:
            work, home, tdir, marks = (os.path.join(tmp, d) for d in
                                       ("work", "home", "tmp", "marks"))
            for d in (work, home, tdir, marks):
                os.mkdir(d)
            make(work, marks)
            with open(os.path.join(work, "deck.nml"), "w") as f:
                f.write(deck_text(geo, meta["deck"], meta["ndim"]))
            shutil.copy(os.path.join(CORPUS, "included", "second.geo"),
                        os.path.join(work, "second.geo"))
            for rc in (".petscrc", "petscrc"):
                with open(os.path.join(work, rc), "w") as f:
                    f.write(f"-info {marks}/petsc_info\n-log_view ascii:{marks}/petsc_log\n"
                            "-malloc_dump\n")
            before = [snapshot(d) for d in (work, home, tdir, marks)]
            fltk_before = fltk_state()
            env = dict(os.environ, HOME=home, TMPDIR=tdir, OMP_NUM_THREADS="1")
            args = [mfcd] + (["--check"] if check_only else []) + ["deck.nml"]
            t0 = time.monotonic()
            try:
                p = subprocess.run(args, cwd=work, env=env, capture_output=True, text=True,
                                   errors="replace", stdin=subprocess.DEVNULL,
                                   timeout=meta["within"] + 60.0)
                code, out, err = p.returncode, p.stdout, p.stderr
            except subprocess.TimeoutExpired:
                code, out, err = None, "", "(killed: no end)"
            elapsed = time.monotonic() - t0
            after = [snapshot(d) for d in (work, home, tdir, marks)]
            problems = []
            if code != meta["exit"]:
                problems.append(f"exit {code}, not {meta['exit']}: {err.strip()[-600:]}")
            if meta["exit"] == 2:
                if "mfcd: error:" not in err or "deck.nml" not in err:
                    problems.append(f"no error naming the deck: {err.strip()[-600:]}")
                for word in meta["expect"]:
                    if word not in err:
                        problems.append(f"message lacks {word!r}: {err.strip()[-800:]}")
                if "root:" in err or "/bin/" in err:
                    problems.append(f"words of another file in the message: {err[-400:]}")
            if elapsed > meta["within"]:
                problems.append(f"took {elapsed:.1f} s, more than {meta['within']:.0f} s")
            if meta["exit"] == 0 and not check_only:
                # the run's own output, and nothing else
                after[0] = {k: v for k, v in after[0].items()
                            if k != "out" and not k.startswith("out" + os.sep)}
            for label_dir, b, a in zip(("working directory", "HOME", "TMPDIR", "markers"),
                                       before, after):
                if a != b:
                    changed = sorted(set(a.items()) ^ set(b.items()))
                    problems.append(f"{label_dir} changed: {changed[:6]}")
            if fltk_state() != fltk_before:
                problems.append("/etc/fltk changed")
            check(label, not problems, "; ".join(problems))


def corpus_cases(mfcd, gmsh, only):
    for fn in sorted(os.listdir(CORPUS)):
        if not fn.endswith(".geo"):
            continue
        name = fn[:-4]
        if only and not any(s in name for s in only):
            continue
        with open(os.path.join(CORPUS, fn), newline="") as f:
            text = f.read()
        meta = header(text)
        if "gmsh" in meta["requires"] and not gmsh:
            print(f"[ SKIP ] hostile_geo.{name}: this mfcd is built without gmsh")
            continue

        def make(work, marks, text=text):
            with open(os.path.join(work, "case.geo"), "w", newline="") as f:
                f.write(text.replace("@MARK@", os.path.join(marks, "marker")))
        run_case(mfcd, name, meta, make)


def made_cases(mfcd, only):
    """The cases whose files are made here (the module's header lists them)."""
    def meta(expect, within=DEFAULT_WITHIN):
        return {"what": "", "expect": expect, "exit": 2, "deck": "", "requires": [],
                "within": within, "ndim": 2}

    def write(path, data, mode="w"):
        with open(path, mode) as f:
            f.write(data)

    def sparse(size):
        def make(work, marks):
            path = os.path.join(work, "case.geo")
            write(path, SQUARE)
            os.truncate(path, size)
        return make

    cases = [
        ("streams_fifo", meta(["is a FIFO (named pipe), not a plain file"]),
         lambda w, m: os.mkfifo(os.path.join(w, "case.geo")), "case.geo"),
        ("streams_link_dev_zero", meta(["is a symbolic link"]),
         lambda w, m: os.symlink("/dev/zero", os.path.join(w, "case.geo")), "case.geo"),
        ("streams_link_passwd", meta(["is a symbolic link"]),
         lambda w, m: os.symlink("/etc/passwd", os.path.join(w, "case.geo")), "case.geo"),
        ("streams_directory", meta(["is a directory, not a plain file"]),
         lambda w, m: os.mkdir(os.path.join(w, "case.geo")), "case.geo"),
        ("streams_sparse_2g", meta(["holds 2147483658 bytes, more than the 1048576 read"]),
         sparse(2**31 + 10), "case.geo"),
        ("streams_sparse_4g", meta(["holds 4294967396 bytes, more than the 1048576 read"]),
         sparse(2**32 + 100), "case.geo"),
        ("streams_one_byte_over", meta(["holds 1048577 bytes, more than the 1048576 read"]),
         lambda w, m: write(os.path.join(w, "case.geo"),
                            SQUARE + "//" + "x" * (2**20 + 1 - len(SQUARE) - 3) + "\n"),
         "case.geo"),
        ("streams_gzip_bytes", meta(["line 1: byte 31 is not plain text"]),
         lambda w, m: write(os.path.join(w, "case.geo"),
                            gzip.compress(SQUARE.encode()), "wb"), "case.geo"),
        ("streams_gz_name", meta(["named *.geo only"]),
         lambda w, m: write(os.path.join(w, "case.geo.gz"),
                            gzip.compress(SQUARE.encode()), "wb"), "case.geo.gz"),
        ("streams_other_file", meta(["named *.geo only"]), lambda w, m: None, "/etc/passwd"),
        ("streams_utf16", meta(["line 1: byte 255 is not plain text"]),
         lambda w, m: write(os.path.join(w, "case.geo"), SQUARE.encode("utf-16"), "wb"),
         "case.geo"),
        ("streams_nul_in_comment", meta(["line 11: byte 0 is not plain text"]),
         lambda w, m: write(os.path.join(w, "case.geo"), SQUARE + "// a\0b\n"), "case.geo"),
        ("sizes_many_names", meta(["line 58011: 'SystemCall' is a gmsh command"]),
         lambda w, m: write(os.path.join(w, "case.geo"), SQUARE + "".join(
             f"a{k:07d} = {k};\n" for k in range(58000)) + 'SystemCall "touch x";\n'),
         "case.geo"),
        ("sizes_deep_nesting", meta(["line 11: expressions nest more than 200 deep"]),
         lambda w, m: write(os.path.join(w, "case.geo"), SQUARE + "x = " + "(" * 500000
                            + "1" + ")" * 500000 + ";\n"), "case.geo"),
        ("sizes_long_name", meta(["line 11: a name is longer than 64 characters"]),
         lambda w, m: write(os.path.join(w, "case.geo"), SQUARE + "y" * 1000 + " = 1;\n"),
         "case.geo"),
    ]
    for name, m, make, geo in cases:
        if only and not any(s in name for s in only):
            continue
        run_case(mfcd, name, m, make, geo)


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    mfcd = os.path.abspath(sys.argv[1])
    only = sys.argv[2:]
    gmsh = has_gmsh(mfcd)
    corpus_cases(mfcd, gmsh, only)
    made_cases(mfcd, only)
    print(f"{sum(results)} of {len(results)} checks passed")
    return 0 if results and all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
