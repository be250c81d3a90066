#!/usr/bin/env bash
# libFuzzer on the input readers (scenario TOML, particle CSV, checkpoint files, mesh files),
# built with clang and ASan+UBSan in build-fuzz/, SECONDS (default 60) per target, seeded with
# the repository's scenarios, CSV files and meshes and a real checkpoint. Any crash, hang
# (>10 s per input) or sanitizer report fails. Run by CI after tools/test.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
source "$root/tools/setup.sh" >/dev/null
for p in clang libclang-rt-14-dev; do
  dpkg -s "$p" >/dev/null 2>&1 || { apt-get update -qq; DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$p" >/dev/null; }
done
CXX=clang++ cmake -S "$root" -B "$root/build-fuzz" -G Ninja -DTSUBU_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
ninja -C "$root/build-fuzz" fuzz_scenario fuzz_csv fuzz_checkpoint fuzz_mesh_file
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work"/{scenario,csv,checkpoint,mesh}
find "$root/examples" "$root/tests" -name '*.toml' -exec cp {} "$work/scenario/" \;
find "$root/examples" "$root/tests" -name '*.csv' -size -64k -exec cp {} "$work/csv/" \;
"$root/build/tsubu" run "$root/tests/scenarios/render_smoke.toml" --out "$work/run" \
  --set output.checkpoint_every_steps=100 --set output.vtk_interval=0 >/dev/null
cp "$work"/run/checkpoint/*.tsbk "$work/checkpoint/"
# fuzz_mesh_file's first byte chooses the reader: "1" for OBJ, "0" for STL.
for f in "$root"/tests/meshes/*; do
  case "$f" in *.obj) kind=1 ;; *) kind=0 ;; esac
  { printf '%s' "$kind"; cat "$f"; } >"$work/mesh/$(basename "$f")"
done
for target in scenario csv checkpoint mesh_file; do
  corpus=${target%_file}
  echo "fuzz_$target: ${seconds} s"
  (cd "$work" && "$root/build-fuzz/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 \
     -print_final_stats=1 "$work/$corpus" 2>&1 | tail -n 12)
done
