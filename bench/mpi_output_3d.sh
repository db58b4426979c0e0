#!/usr/bin/env bash
# The output's cost on ranks (doc/parallel.md, "Snapshots and checkpoints from the parts"):
# the 3D Taylor bench (bench/decks/taylor_bar_3d_rkpm_bench.nml, 37,467 particles) cut to its
# first 40 steps with a snapshot every 4 steps and a checkpoint every 10, on each rank count
# given, one thread a rank. Prints the summary's time-loop seconds and output share, the
# log's count of gathers to rank 0, and every rank's peak resident memory.
# Usage: bash bench/mpi_output_3d.sh [MPI_BIN_DIR] [RANKS ...]
#   default: build-mpi-rel/bin (bench/mpi_scaling.sh builds it), ranks 1 2
# Give another MPI_BIN_DIR (e.g. a build of an earlier commit) for a before/after pair.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "${1:-$root/build-mpi-rel/bin}" && pwd)
shift || true
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2)
[ -x /usr/bin/time ] || { echo "mpi_output_3d: needs GNU time (apt-get install time)" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# 40 steps of 15 ns; snapshots at 0, 60, ..., 600 ns (11); a checkpoint every 10 steps (4)
snaps=$(python3 -c "print(', '.join(f'{k*6.0e-8:.3e}' for k in range(11)))")
sed -e "s#file = 'output/#file = '$work/#" -e 's/t_end = 4.5e-6/t_end = 6.0e-7/' \
  -e 's/log_every = 100/log_every = 10/' -e "s/snapshot_times = 0.0/snapshot_times = $snaps/" \
  -e "s#^&output#\&output\n  checkpoint_every = 10#" \
  "$root/bench/decks/taylor_bar_3d_rkpm_bench.nml" > "$work/t.nml"
echo "# mfcd_mpi output cost, 3D Taylor bench, 40 steps, 11 snapshots, 4 checkpoints"
echo "- date: $(date -Iseconds); commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null); bin: $bin"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
for n in "${ranks[@]}"; do
  echo "== $n rank(s)"
  rm -f "$work"/taylor_bar_3d_rkpm_bench*
  (cd "$work" && mpiexec --oversubscribe --bind-to none -n "$n" /usr/bin/time -f "mem %M KB" \
    "$bin/mfcd_mpi" t.nml > log.txt 2> err.txt) || { tail -5 "$work/err.txt"; exit 1; }
  grep -E 'steps to t =|summary: time loop|gathered to rank 0' "$work/log.txt" \
    | sed 's/^/  /'
  grep 'mem ' "$work/err.txt" | sed 's/^/  /'
  ls -l "$work"/taylor_bar_3d_rkpm_bench.h5 | awk '{print "  file bytes", $5}'
done
