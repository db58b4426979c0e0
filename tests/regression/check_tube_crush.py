"""The tube crush (issue 24, the paper's Fig. 1 case), coarse, for CI: input/tube_crush_
coarse.nml (a quarter tube of gmsh tetrahedra, 12 mm long, 1.4 tetrahedra through the
wall, crushed 8 mm by a rigid ram, without self-contact) is run and post/tube_crush.py
--control-only checks it (its --help and doc/self_contact.md, "The tube crush (Fig. 1)",
give each reason):

  the first fold closes (a lobe of the section's radial profile whose two arms have both
     shortened along the axis to less than half their length);
  the mode is axisymmetric (the generators in the two symmetry planes differ by at most
     25% of the largest radial excursion), the mode of the estimate;
  the mean crush force within 25% of Abramowicz & Jones's (1984) estimate with the
     effective crushing distance (measured -7.6%; over the first fold only);
  the plastic work from the element strains equals /history/w_plastic within 5%;
  the energy residual below 1% of its scale.
The self-contact of the folds is checked by the fine pair (bash tools/tube_crush.sh): with
the pair this coarse run costs three times as much and its faces meet only after 228 us.

Usage: check_tube_crush.py /path/to/mfcd COARSE_DECK
Exit 77 (skipped) when mfcd is built without gmsh.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")


def run(mfcd, deck, work):
    """Run deck in work, the gmsh script it names copied there; the output's path."""
    text = open(deck).read()
    for geo in re.findall(r"^\s*file\s*=\s*'([^']+\.geo)'", text, re.M):
        os.makedirs(os.path.join(work, os.path.dirname(geo)), exist_ok=True)
        shutil.copy(os.path.join(ROOT, geo), os.path.join(work, geo))
    t0 = time.time()
    p = subprocess.run([mfcd, deck], cwd=work, capture_output=True, text=True, timeout=1800,
                       env=dict(os.environ, OMP_NUM_THREADS=os.environ.get(
                           "OMP_NUM_THREADS", "1")))
    print(f"tube_crush: {os.path.basename(deck)}: exit {p.returncode} in "
          f"{time.time() - t0:.1f} s")
    if p.returncode:
        print(p.stderr[-2000:])
        return None
    out = re.findall(r"^\s*file\s*=\s*'([^']+\.h5)'", text, re.M)[0]
    return os.path.join(work, out)


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    mfcd, deck = (os.path.abspath(a) for a in sys.argv[1:3])
    v = subprocess.run([mfcd, "--version"], capture_output=True, text=True).stdout
    if not any(line.startswith("gmsh 4") for line in v.splitlines()):
        print("tube_crush: mfcd is built without gmsh (bash tools/setup.sh --gmsh, then "
              "rebuild): skipped")
        return 77
    work = tempfile.mkdtemp(prefix="mfcd_tube_crush_")
    try:
        h5 = run(mfcd, deck, work)
        if h5 is None:
            return 1
        sys.path.insert(0, os.path.join(ROOT, "post"))
        import tube_crush
        return tube_crush.main([h5, "--control-only", "--min-folds", "1",
                                "--overlap-last", "1"])
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
