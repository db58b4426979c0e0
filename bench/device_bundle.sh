#!/usr/bin/env bash
# Packs mfcd_mpi with the Open MPI it was built against into one folder that runs on a
# machine without MPI (a lent machine with more cores, doc/parallel.md "3D on 16 cores"):
# the program, mpirun (orterun), GNU time, Open MPI's and PMIx's plugins and help files laid
# out under usr/ as on Debian 12, and every shared library these load but glibc's own.
# Open MPI and PMIx find their plugins through OPAL_PREFIX and PMIX_PREFIX, the libraries
# through LD_LIBRARY_PATH: `source DIR/env.sh` sets all three.
# Usage: bash bench/device_bundle.sh [BIN_DIR] [DIR]
#   default: build-mpi-rel/bin, .devb; also packs DIR.tar.xz (move it into a folder that
#   .git/info/exclude ignores, carry that, and unpack it there with tar xJf)
# Check it here with the system's MPI hidden: bash bench/device_bundle.sh --check [DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ "${1:-}" = --check ]; then
  # Hide Debian's Open MPI and PMIx in a private mount namespace, then run 2 ranks from DIR.
  dir=$(cd "${2:-$root/.devb}" && pwd)
  exec unshare -m bash -c '
    set -e
    e=$(mktemp -d)
    for p in /usr/lib/x86_64-linux-gnu/openmpi /usr/lib/x86_64-linux-gnu/pmix2 \
             /usr/share/openmpi /etc/openmpi; do mount --bind "$e" "$p"; done
    for p in /usr/bin/orterun /usr/bin/orted /usr/lib/x86_64-linux-gnu/libmpi.so.40 \
             /usr/lib/x86_64-linux-gnu/libopen-pal.so.40; do mount --bind /dev/null "$p"; done
    source "$1/env.sh"
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    w=$(mktemp -d)
    sed "s#output/#$w/#" "$2/tests/mpi/slab_impact_3d.nml" > "$w/d.nml"
    mpirun --oversubscribe -np 2 "$1/usr/bin/time" -f "rank %M kB" "$1/usr/bin/mfcd_mpi" \
      "$w/d.nml" 2>&1 | grep -E "summary: (MPI|time loop)|rank [0-9]+ kB|rror"
    ls -l "$w"
  ' sh "$dir" "$root"
fi
bin=$(cd "${1:-$root/build-mpi-rel/bin}" && pwd)
dir=${2:-$root/.devb}
rm -rf "$dir"
mkdir -p "$dir/lib" "$dir/usr/bin"
dir=$(cd "$dir" && pwd)
ml=/usr/lib/x86_64-linux-gnu
cp "$bin/mfcd_mpi" /usr/bin/orterun "$dir/usr/bin/"
[ -x /usr/bin/time ] && cp /usr/bin/time "$dir/usr/bin/"
ln -s orterun "$dir/usr/bin/mpirun"
ln -s orterun "$dir/usr/bin/mpiexec"
mkdir -p "$dir/usr/lib/x86_64-linux-gnu/openmpi/lib" "$dir/usr/share"
# Plugins, but those for networks a single machine does not have (their libraries are large).
mkdir -p "$dir$ml/openmpi/lib/openmpi3"
for f in "$ml"/openmpi/lib/openmpi3/*.so; do
  case $(basename "$f") in
    *ucx*|*ofi*|*openib*|*psm*|*usnic*|*verbs*|*java*|*cuda*|*portals*) continue ;;
  esac
  cp "$f" "$dir$ml/openmpi/lib/openmpi3/"
done
cp -r "$ml/pmix2" "$dir$ml/"
rm -rf "$dir$ml"/pmix2/lib/*.a "$dir$ml"/pmix2/include
cp -r /usr/share/openmpi "$dir/usr/share/"
# Every shared library the program, mpirun and the plugins load, but glibc's.
objs=("$dir/usr/bin/mfcd_mpi" "$dir/usr/bin/orterun" "$dir$ml"/openmpi/lib/openmpi3/*.so
      "$dir$ml"/pmix2/lib/pmix/*.so)
ldd "${objs[@]}" 2>/dev/null | awk '/=> \//{print $3}' | sort -u | while read -r lib; do
  case $(basename "$lib") in
    libc.so*|libm.so*|libdl.so*|librt.so*|libpthread.so*|ld-linux*|libresolv.so*) continue ;;
    libpmix.so*) continue ;;  # in pmix2/lib
  esac
  cp -L "$lib" "$dir/lib/"
done
cat > "$dir/env.sh" <<'EOF'
b=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export OPAL_PREFIX=$b/usr PMIX_PREFIX=$b/usr/lib/x86_64-linux-gnu/pmix2
export PATH=$b/usr/bin:$PATH
export LD_LIBRARY_PATH=$b/lib:$b/usr/lib/x86_64-linux-gnu/openmpi/lib:$PMIX_PREFIX/lib
# one machine: shared memory between ranks, no network plugins to look for
export OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1 OMPI_MCA_mca_base_component_show_load_errors=0
EOF
# The machine's copy travels packed (its size counts against what a call may carry).
tar -C "$(dirname "$dir")" -cJf "$dir.tar.xz" "$(basename "$dir")"
du -sh "$dir" "$dir.tar.xz"
