#!/usr/bin/env bash
# Heap allocations a time step (the house's habit: no allocation in the time loop): each
# deck run twice, cut to 20 and to 120 steps by max_steps, with a malloc counter preloaded
# (a few lines of C, built here with gcc); the difference over 100 is the allocations of a
# step, the set-up's cancelling. What is left is the output's: each step's history row
# appended to the HDF5 file (the HDF5 library's own allocations, a crash keeps the rows so
# far) and the log's lines. Not a test: the count depends on the HDF5 and libgfortran
# versions. Results in doc/benchmarks.md ("Allocations in the time loop").
# Usage: bash bench/alloc_per_step.sh MFCD [DECK ...]
#   (default decks: the Taylor bar coarse by RKPM and by FEM, the bars' collision (det(M)
#   both ways), the C-shape's self-contact)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
shift
decks=("$@")
[ ${#decks[@]} -gt 0 ] || decks=(input/taylor_bar_rkpm_coarse.nml input/taylor_bar_fem_coarse.nml
  input/bars_collision_elastic.nml input/c_shape_fold.nml)
command -v gcc > /dev/null || { echo "alloc_per_step: needs gcc (apt-get install gcc)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/count.c" <<'C'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
static atomic_long calls;
static void *(*next_malloc)(size_t);
void *malloc(size_t size) {
  if (!next_malloc) next_malloc = (void *(*)(size_t))dlsym(RTLD_NEXT, "malloc");
  atomic_fetch_add(&calls, 1);
  return next_malloc(size);
}
__attribute__((destructor)) static void report(void) {
  fprintf(stderr, "alloc_per_step: malloc calls %ld\n", (long)calls);
}
C
gcc -O2 -shared -fPIC -o "$work/count.so" "$work/count.c" -ldl
echo "# heap allocations a step: $bin"
echo "- date: $(date -Iseconds); repository at $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), one thread"
for deck in "${decks[@]}"; do
  counts=()
  for n in 20 120; do
    sed -e "s#file = 'output/#file = '$work/#" -e "0,/&solver/s//\&solver\n  max_steps = $n/" \
      "$root/$deck" > "$work/d.nml"
    c=$(cd "$root" && OMP_NUM_THREADS=1 LD_PRELOAD="$work/count.so" "$bin" "$work/d.nml" 2>&1 \
      > /dev/null | sed -n 's/^alloc_per_step: malloc calls //p' | tail -1)
    counts+=("$c")
  done
  awk -v d="$deck" -v a="${counts[0]}" -v b="${counts[1]}" \
    'BEGIN { printf "%s: %d calls at 20 steps, %d at 120: %.1f a step\n", d, a, b, (b - a)/100 }'
done
