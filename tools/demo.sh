#!/usr/bin/env bash
# The main job: build tsubu, settle ~2700 polydisperse grains (examples/settle-poly.toml),
# write ParaView files and a picture of the bed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/tools/setup.sh"
out="$root/out/settle-poly"
# --overwrite: the demo replaces its previous run.
"$root/build/tsubu" run "$root/examples/settle-poly.toml" --out "$out" --overwrite --threads "$(nproc)"
/usr/bin/python3 "$root/tools/render_bed.py" "$out"
echo "ParaView: open $out/frames/particles.pvd"
