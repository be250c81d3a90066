// A sum of doubles that does not depend on the order of its terms: the terms are kept
// exactly as a few non-overlapping partial sums (Shewchuk 1997, "Adaptive precision
// floating-point arithmetic and fast robust geometric predicates", Discrete & Computational
// Geometry 18, 305-363, the expansion sum), and value() rounds their exact total once, to
// the nearest double (ties to even). Global quantities (energies, volumes, loads) summed
// over particles or contacts therefore have the same bits however the particles are
// numbered or split among threads or processes: two ExactSums of parts, merged, give the
// sum of all terms.
//
// Cost: each term walks the partials (one or two for terms of one sign and similar size).
// Terms that are not finite, or partials that overflow, make the value their plain sum
// (inf or NaN, whatever the order).
#pragma once
#include <cmath>
#include <utility>
#include <vector>

namespace tsubu {

class ExactSum {
 public:
  ExactSum& operator+=(double x) {
    if (x == 0) return *this;  // a sum of zeros (of either sign) is +0
    if (!std::isfinite(x)) {
      special_ += x;
      return *this;
    }
    std::size_t kept = 0;
    for (double y : partials_) {
      if (std::fabs(x) < std::fabs(y)) std::swap(x, y);
      const double hi = x + y, lo = y - (hi - x);  // hi + lo = x + y exactly (|x| >= |y|)
      if (lo != 0) partials_[kept++] = lo;
      x = hi;
    }
    partials_.resize(kept);
    if (std::isfinite(x)) partials_.push_back(x);
    else special_ += x;  // the partials overflowed
    return *this;
  }
  ExactSum& operator+=(const ExactSum& other) {
    for (double y : other.partials_) *this += y;
    special_ += other.special_;
    return *this;
  }

  // The exact sum rounded to the nearest double.
  double value() const {
    if (special_ != 0 || std::isnan(special_)) return special_;
    std::size_t n = partials_.size();
    if (n == 0) return 0;
    // The partials are non-overlapping and increasing in magnitude: add from the largest
    // down until a rounding error appears; then correct a tie that the rest breaks.
    double hi = partials_[--n], lo = 0;
    while (n > 0) {
      const double x = hi, y = partials_[--n];
      hi = x + y;
      lo = y - (hi - x);
      if (lo != 0) break;
    }
    if (n > 0 && ((lo < 0 && partials_[n - 1] < 0) || (lo > 0 && partials_[n - 1] > 0))) {
      const double y = 2 * lo, x = hi + y;
      if (y == x - hi) hi = x;
    }
    return hi;
  }

 private:
  std::vector<double> partials_;  // increasing magnitude, non-overlapping
  double special_ = 0;            // the plain sum of the terms that are not finite
};

}  // namespace tsubu
