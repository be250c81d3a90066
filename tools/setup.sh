#!/usr/bin/env bash
# Installs what tsubu needs from Debian (when missing), builds it in build/ (Release) and
# makes `import tsubu` work for /usr/bin/python3 (docs/python.md). Sourced by tools/demo.sh
# and tools/test.sh.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# libopenmpi-dev and openmpi-bin: runs split among processes (docs/parallel.md) and their
# tests; slurm-wlm, openmpi-bin and python3-mpi4py: the sweep's Slurm and MPI engines and their
# tests (python/tests/test_sweep_cluster.py starts a Slurm of its own; no service is configured).
packages=(cmake ninja-build g++ libgtest-dev libbenchmark-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
          python3-vtk9 python3-matplotlib python3-numpy pybind11-dev python3-dev python3-pytest
          libopenmpi-dev slurm-wlm openmpi-bin python3-mpi4py)
sudo=""; [ "$(id -u)" = 0 ] || sudo=sudo
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C "$root/build"
# The Python module: a .pth file in /usr/bin/python3's site-packages puts build/python (the
# package tsubu, python/CMakeLists.txt) on its module path; rewritten only when it differs.
site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
if [ "$(cat "$site/tsubu.pth" 2>/dev/null)" != "$root/build/python" ]; then
  $sudo mkdir -p "$site"
  echo "$root/build/python" | $sudo tee "$site/tsubu.pth" >/dev/null
  echo "import tsubu: $site/tsubu.pth -> $root/build/python"
fi
