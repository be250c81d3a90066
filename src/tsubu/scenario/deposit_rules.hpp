// The two rules for the height of a deposit (docs/sedimentation.md, "Measurements on the
// deposit"), as a scenario gives them; analysis/deposit.hpp measures by them.
#pragma once

namespace tsubu {

// The deposit's surface, the default rule for the deposit height (docs/sedimentation.md,
// "Deposit height"): the solid fraction of a window of thickness `window` (about d_max)
// that slides up from `floor` in steps of window/8; the surface is where it first falls
// below half the largest value met below it (that value taken as at least
// kDepositSolidFraction), interpolated linearly between steps. A deposit of uniform solid
// fraction above kDepositSolidFraction with a flat top at h gives h exactly, whatever its
// density; it reports a height from the first grains on and rises as grains land, and a
// cloud of falling grains looser than kDepositSolidFraction / 2 is not taken for deposit.
// While the window on the floor is less than half full, the height is its centre scaled by
// its fill (0 for no grain within `window` of the floor). Windows reach up to `top`.
inline constexpr double kDepositSolidFraction = 0.4;  // looser than any deposit of spheres at rest
struct SurfaceRule {
  double floor = 0;   // m
  double window = 0;  // m
  double top = 0;     // m
};

// The experiment's slice rule for the deposit height (the paper's protocol): slices of
// `slice` from `floor`; the deposit has reached z_k = floor + k slice once the solid fraction
// of floor < z < z_k exceeds `threshold`. The height is z_k - floor for the largest such
// k <= slices (0: none).
struct SliceRule {
  double floor = 0;       // m
  double slice = 0;       // m, 0.1 L in the experiment
  int slices = 10;        // up to floor + 10 slices = L
  double threshold = 0.6; // solid fraction
};

}  // namespace tsubu
