#!/usr/bin/env bash
# Installs what the `bench` target needs besides the build: Debian's PyTorch and torchaudio, which
# it runs in the same session as our programs to measure the rates it compares against
# (tests/benchmarks/pytorch_anchors.py). Not part of the default bootstrap. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/debian_packages.sh
install_missing_packages python3-torch python3-torchaudio
