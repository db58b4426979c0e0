#!/usr/bin/env python3
"""The mfcd program's command line and bad-input handling (issue 2, item 6).

Every bad deck must exit with code 2, print one message naming the deck, the group, the
variable and the fix, and write no output file. Standard library only.
Usage: test_cli.py /path/to/mfcd
"""
import os
import subprocess
import sys
import tempfile

MFCD = os.path.abspath(sys.argv[1])
results = []


def run(args, cwd):
    p = subprocess.run([MFCD] + args, cwd=cwd, capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


def check(name, cond, detail=""):
    results.append((name, cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + name + ("" if cond else ": " + detail))


GOOD_BODY = """&body
  name = 'block'
  shape = 'rectangle'
  lo = 0.0, 0.0
  hi = 1.0, 1.0
  n = 11, 11
/
"""
DETECTION = """&detection
  grid_lo = -0.5, -0.5
  grid_hi = 1.5, 1.5
  grid_n = 21, 21
/
"""


def deck(run_group="&run ndim = 2 /\n", body=GOOD_BODY, detection=DETECTION,
         output="&output file = 'out/OUT.h5' /\n"):
    return run_group + body + detection + output


def bad_case(tmp, name, text, words, out="out/OUT.h5", regular_file=None):
    d = os.path.join(tmp, name)
    os.makedirs(d)
    if regular_file:
        open(os.path.join(d, regular_file), "w").close()
    path = os.path.join(d, "deck.nml")
    with open(path, "w") as f:
        f.write(text.replace("OUT", name))
    rc, out_s, err_s = run([path], d)
    target = os.path.join(d, out.replace("OUT", name))
    check(f"{name}: exit code 2", rc == 2, f"rc={rc} stderr={err_s!r}")
    missing = [w for w in [path] + words if w not in err_s]
    check(f"{name}: message names {', '.join(words)}", not missing,
          f"missing {missing} in {err_s!r}")
    check(f"{name}: one error line", err_s.count("mfcd: error:") == 1, err_s)
    check(f"{name}: no output written", not os.path.exists(target)
          and not os.path.exists(target + ".probe"), target)


def main():
    tmp = tempfile.mkdtemp(prefix="mfcd_cli_")
    rc, out, _ = run(["--help"], tmp)
    check("--help exits 0 and shows usage", rc == 0 and "usage: mfcd" in out, out)
    rc, out, _ = run(["--version"], tmp)
    check("--version exits 0 and names the commit", rc == 0 and "mfcd " in out and "git" in out,
          out)
    rc, _, err = run(["--bogus"], tmp)
    check("unknown option exits 2", rc == 2 and "--bogus" in err, err)
    rc, _, err = run([], tmp)
    check("no deck exits 2", rc == 2 and "no deck" in err, err)
    rc, _, err = run([os.path.join(tmp, "missing.nml")], tmp)
    check("missing deck exits 2 naming it", rc == 2 and "missing.nml" in err, err)
    # the deck is read once, as a plain file: a FIFO (here with no writer, which would
    # block an open) or a directory is refused at once, by the run and by --check
    os.mkfifo(os.path.join(tmp, "fifo.nml"))
    os.mkdir(os.path.join(tmp, "dir.nml"))
    for name, kind in (("fifo.nml", "is a FIFO (named pipe)"), ("dir.nml", "is a directory")):
        for args in ([], ["--check"]):
            rc, _, err = run(args + [os.path.join(tmp, name)], tmp)
            check(f"deck {name} {' '.join(args)}: exit 2, '{kind}'",
                  rc == 2 and kind in err and name in err, err)
    # a link to a deck is the user's own path: followed
    with open(os.path.join(tmp, "real.nml"), "w") as f:
        f.write(deck())
    os.symlink("real.nml", os.path.join(tmp, "link.nml"))
    rc, _, err = run(["--check", os.path.join(tmp, "link.nml")], tmp)
    check("deck given through a link: followed", rc == 0, err)

    bad_case(tmp, "misspelt", deck(body=GOOD_BODY.replace("  n = 11", "  nn = 11")),
             ["&body", "'nn'", "did you mean 'n'"])
    bad_case(tmp, "kernel", deck(body=GOOD_BODY.replace("/\n", "  kernel = 'spline'\n/\n")),
             ["&body", "kernel", "'spline'", "'cubic_spline', 'quartic'"])
    bad_case(tmp, "basis", deck(body=GOOD_BODY.replace("/\n", "  basis = 'cubic'\n/\n")),
             ["&body", "basis", "'cubic'", "bilinear"])
    bad_case(tmp, "window", deck(body=GOOD_BODY.replace("/\n", "  window = 'box'\n/\n")),
             ["&body", "window", "'box'", "'tensor', 'radial'"])
    bad_case(tmp, "shape", deck(body=GOOD_BODY.replace("'rectangle'", "'square'")),
             ["&body", "shape", "'square'", "rectangle"])
    bad_case(tmp, "ndim", deck(run_group="&run ndim = 5 /\n"), ["&run", "ndim", "[1, 3]"])
    bad_case(tmp, "group", deck(run_group="&runn ndim = 2 /\n"), ["&runn", "valid groups"])
    bad_case(tmp, "eps", deck(detection=DETECTION.replace("/\n", "  eps_cr = 0.0\n/\n")),
             ["&detection", "eps_cr", "5e-10"])
    bad_case(tmp, "support", deck(body=GOOD_BODY.replace("/\n", "  support_factor = 0.8\n/\n")),
             ["&body", "support_factor", "Theorem 3.1", ">= 1.01"])
    bad_case(tmp, "detbody", deck(detection=DETECTION.replace("/\n", "  body = 'nope'\n/\n")),
             ["&detection", "body", "'nope'", "block"])
    # an output path under a regular file cannot be created
    bad_case(tmp, "unwritable", deck(output="&output file = 'afile/sub/OUT.h5' /\n"),
             ["&output", "file", "writable"], out="afile/sub/OUT.h5", regular_file="afile")
    # an existing output file with overwrite = .false. is kept untouched
    d = os.path.join(tmp, "keep")
    os.makedirs(os.path.join(d, "out"))
    target = os.path.join(d, "out", "keep.h5")
    with open(target, "w") as f:
        f.write("precious")
    path = os.path.join(d, "deck.nml")
    with open(path, "w") as f:
        f.write(deck(output="&output file = 'out/keep.h5', overwrite = .false. /\n"))
    rc, _, err = run([path], d)
    check("overwrite = .false.: exit 2 naming the fix", rc == 2 and "overwrite" in err, err)
    check("overwrite = .false.: file untouched", open(target).read() == "precious")

    # a good deck: --check writes nothing; a run writes the file and exits 0
    d = os.path.join(tmp, "good")
    os.makedirs(d)
    path = os.path.join(d, "deck.nml")
    with open(path, "w") as f:
        f.write(deck().replace("OUT", "good"))
    rc, out, err = run(["--check", path], d)
    check("--check on a good deck exits 0, writes nothing",
          rc == 0 and not os.path.exists(os.path.join(d, "out", "good.h5")), err)
    rc, out, err = run([path], d)
    check("good deck runs", rc == 0 and os.path.exists(os.path.join(d, "out", "good.h5")), err)
    check("log echoes the deck", "deck| &output" in out, out[:500])

    npass = sum(1 for _, ok in results if ok)
    nfail = len(results) - npass
    print(f"{npass} passed, {nfail} failed")
    sys.exit(1 if nfail else 0)


if __name__ == "__main__":
    main()
