// Key postures interpolated with a Kochanek–Bartels spline: a cubic Hermite
// spline whose tangents each key shapes with tension, continuity and bias.
// Turner's LEMAN animates its skeleton this way (Turner, "LEMAN: A System for
// Constructing and Animating Layered Elastic Characters", §5.7: key postures
// whose joint angles are interpolated by [Kochanek 84]); the tangents are
// those of Kochanek & Bartels, "Interpolating Splines with Local Tension,
// Continuity, and Bias Control", SIGGRAPH '84.
//
// T = C = B = 0 everywhere gives a Catmull–Rom spline; T = 1 gives zero
// tangents (an ease in and out of every key); C = -1 gives tangents along the
// neighbouring chords (piecewise linear when the keys are evenly spaced).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace sinew::motion {

struct KeyPosture {
  double time = 0;             // seconds; keys strictly increasing in time
  std::vector<double> values;  // joint values (e.g. degrees), the same count in every key
  double tension = 0;          // each in [-1, 1]
  double continuity = 0;
  double bias = 0;
};

class KbSpline {
 public:
  // Validates the keys (at least one; strictly increasing finite times; equal
  // value counts; finite values; T, C, B in [-1, 1]) and precomputes the
  // tangents. On failure returns false and sets `error` to "key <i>: <problem>".
  static bool create(std::vector<KeyPosture> keys, KbSpline* out, std::string* error);

  size_t dimension() const { return dimension_; }
  const std::vector<KeyPosture>& keys() const { return keys_; }

  // Values at `time`, held at the first and last key outside their range
  // (NaN counts as before the start). `out` must have dimension() elements.
  void sample(double time, std::span<double> out) const;
  std::vector<double> sample(double time) const;

  // Tangent leaving key i (starts segment i -> i+1) and tangent arriving at
  // key i (ends segment i-1 -> i), per unit of the segment's parameter s in [0, 1].
  std::span<const double> outgoing_tangent(size_t key) const;
  std::span<const double> incoming_tangent(size_t key) const;

 private:
  std::vector<KeyPosture> keys_;
  size_t dimension_ = 0;
  std::vector<double> outgoing_;  // keys_.size() rows of dimension_
  std::vector<double> incoming_;
};

}  // namespace sinew::motion
