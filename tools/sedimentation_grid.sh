#!/usr/bin/env bash
# Runs the sedimentation report's sweeps (docs/validation/sedimentation.md) in the order the
# report needs them, cheapest first, two runs at a time, then redraws the report's figures
# and CSV. Each sweep skips its finished cases and resumes its interrupted ones from their
# checkpoints, so the script can be stopped (Ctrl-C) and started again at any time; a run
# longer than the session is not lost. About ten core-days in all (96 core-hours for the 698
# runs made by 2026-12-06); the mixtures of Sigma = 2.77 at the lowest fluxes take most of it:
# S = 0 at 0.1 Q_0 at rest, about 20 core-hours a run.
#
#   bash tools/sedimentation_grid.sh            # everything
#   bash tools/sedimentation_grid.sh one-size   # the one-size sweeps only (about an hour)
#
# Uses build/tsubu and the build's Python package (bash tools/setup.sh builds them); runs
# at the lowest priority (nice 19) so that the machine stays usable.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
trap 'exit 130' INT TERM  # Ctrl-C stops the grid (each sweep stops its runs at a checkpoint first)
export PYTHONPATH="$root/build/python${PYTHONPATH:+:$PYTHONPATH}"
sweeps=examples/sedimentation/sweeps
# A sweep with failed cases says so in its results.csv and on stdout; the grid goes on.
sweep() {
  nice -n 19 /usr/bin/python3 -m tsubu.sweep "$sweeps/$1.toml" --jobs 2 "${@:2}" ||
    echo "sedimentation_grid: sweep $1 did not finish every case; see out/sweeps/$1/results.csv"
}
spread=particles.0.distribution.spread
q0=particles.0.solid_fraction=0.1

# One size (Figs. 5-6, box size, vacuum, hindered settling, no friction).
for name in fig5-6 fig5-6-stop vacuum rcp-mono fig5-6-hindered finite-size; do sweep "$name"; done
if [[ "${1:-}" != one-size ]]; then
  # Mixtures at Q_0, the paper's protocol beside, Fig. 8, the box, no friction, hindered.
  for s in 0.6931 1.3863 2.0794; do
    sweep fig7-rest --only "$spread=$s" --only "$q0"
    sweep fig7-stop --only "$spread=$s" --only "$q0"
  done
  sweep fig8
  sweep box
  sweep rcp
  sweep readings
  # The lower fluxes, narrow to wide, then Sigma = 2.77 and the rest of both protocols.
  for s in 0.6931 1.3863 2.0794; do sweep fig7-rest --only "$spread=$s"; done
  sweep fig7-rest
  sweep fig7-stop
  sweep fig7-hindered
fi
/usr/bin/python3 tools/plot_sedimentation.py
