#!/usr/bin/env bash
# Installs the Debian 12 packages fscil-bench needs (only those missing), makes OpenBLAS the
# system BLAS, then configures and builds Release into build/: the program and its man page (the
# README's first command), or with --tests everything, tests and benchmarks too (its second).
# Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "") targets=(--target fscil_program) ;;
  --tests) targets=() ;;
  *) echo "bootstrap.sh: unknown argument '$1' (expected nothing, or --tests)" >&2; exit 2 ;;
esac
source tools/debian_packages.sh

packages=(
  build-essential cmake ninja-build git pkg-config ccache
  libtorch-dev libopenblas0-openmp
  libfftw3-dev libhdf5-dev libsndfile1-dev
  libfluidsynth-dev musescore-general-soundfont  # sf-instruments: notes rendered from its SoundFont
  libfmt-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev llvm-14  # tests/fuzz: libFuzzer and sanitizer runtimes, llvm-symbolizer
  chromium  # the report page test: index.html and its figures opened in headless Chromium
  slurm-wlm munge  # the Slurm tests: tools/slurm_local.sh runs a single-node cluster from them
  help2man  # the man page, from --help-all
  python3-torch python3-h5py  # tests that read a saved model and our HDF5 files from Python
  texlive-latex-base texlive-latex-recommended texlive-pictures  # the LaTeX test: every .tex compiles
)

install_missing_packages "${packages[@]}"

# Debian links LibTorch against the reference BLAS (~2 GFLOP/s); OpenBLAS gives ~100x on matmul.
arch_dir=/usr/lib/x86_64-linux-gnu
for library in libblas.so.3 liblapack.so.3; do
  link="${library}-x86_64-linux-gnu"
  target="$arch_dir/openblas-openmp/$library"
  if [ -e "$target" ] && [ "$(readlink -f "$arch_dir/$library")" != "$target" ]; then
    as_root update-alternatives --set "$link" "$target"
  fi
done

# Ninja compiles a target's files while the libraries it links are still being built (make waits
# for them): 2 cores stay busy. A build folder configured before keeps its generator.
generator=()
[ -f build/CMakeCache.txt ] || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" "${targets[@]}"
