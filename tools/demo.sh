#!/usr/bin/env bash
# The main job: build tsubu, rain ~1000 quartz grains of 3-10 mm into still water at a given
# flux until 0.2 kg have entered and the deposit is at rest (examples/sedimentation/rain.toml,
# about a minute and a half of one core once built), and draw the
# deposit with its porosity and grading profiles.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
source "$root/tools/setup.sh"
out="$root/out/rain"
# --overwrite: the demo replaces its previous run.
"$root/build/tsubu" run "$root/examples/sedimentation/rain.toml" --out "$out" --overwrite --threads "$(nproc)"
/usr/bin/python3 "$root/tools/render_deposit.py" "$out"
echo "ParaView: open $out/frames/particles.pvd (and contacts.pvd, walls.pvd)"
