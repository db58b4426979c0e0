#!/usr/bin/env bash
# The scaling runs made on a lent machine with more cores and no MPI (doc/parallel.md, "3D on
# 16 cores"): unpacks the bundle of bench/device_bundle.sh, then runs the weak scaling of
# bench/mpi_weak_3d.sh (50 steps, 1 to 16 ranks) and the strong scaling of
# bench/mpi_strong_3d.sh, each log written to OUT as it goes.
# Usage: bash bench/device_run.sh BUNDLE.tar.xz OUT [WEAK_RANKS] [STRONG_RUNS]
#   default: "1 2 4 8 16" and "16x1 8x1 4x1 2x1 1x1 4x4 1x16"
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tarball=$1
out=$2
weak=${3:-1 2 4 8 16}
strong=${4:-16x1 8x1 4x1 2x1 1x1 4x4 1x16}
mkdir -p "$out" /tmp/mfcd_dev
tar -C /tmp/mfcd_dev -xJf "$tarball"
b=/tmp/mfcd_dev/$(tar -tJf "$tarball" | head -1 | cut -d/ -f1)
[ -x "$b/usr/bin/mfcd_mpi" ] || { echo "device_run: no usr/bin/mfcd_mpi in $tarball" >&2; exit 2; }
# shellcheck disable=SC1091
source "$b/env.sh"
[ -x /usr/bin/time ] || cp "$b/usr/bin/time" /usr/bin/time
# Open MPI's and PMIx's compiled-in paths, where the machine has none of its own
for p in usr/lib/x86_64-linux-gnu/pmix2 usr/lib/x86_64-linux-gnu/openmpi usr/share/openmpi; do
  [ -e "/$p" ] || ln -s "$b/$p" "/$p"
done
export OMPI_MCA_btl_vader_backing_directory=/tmp
{
  echo "# machine"
  date -Iseconds
  grep -m1 'model name' /proc/cpuinfo
  nproc
  lscpu 2>/dev/null | grep -E 'Socket|Core|Thread|NUMA|L3' || true
  free -g
} > "$out/machine.txt" 2>&1
cat "$out/machine.txt"
# shellcheck disable=SC2086
STEPS=50 bash "$root/bench/mpi_weak_3d.sh" "$b/usr/bin" $weak 2>&1 | tee "$out/weak.txt"
# shellcheck disable=SC2086
bash "$root/bench/mpi_strong_3d.sh" "$b/usr/bin" $strong 2>&1 | tee "$out/strong.txt"
