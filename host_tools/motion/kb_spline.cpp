#include "kb_spline.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "text_scan.hpp"

namespace sinew::motion {

namespace {

// The shortest text that reads back as `v` (std::to_string would print 1.000000).
std::string shortest(double v) {
  std::array<char, 32> text{};
  const auto result = std::to_chars(text.data(), text.data() + text.size(), v);
  return std::string(text.data(), result.ptr);
}

bool in_unit_range(double v) { return std::isfinite(v) && v >= -1 && v <= 1; }

std::string key_error(size_t key, const std::string& problem) {
  return cat("key ", std::to_string(key), ": ", problem);
}

bool validate(const std::vector<KeyPosture>& keys, std::string* error) {
  if (keys.empty()) {
    *error = "no key postures";
    return false;
  }
  for (size_t i = 0; i < keys.size(); ++i) {
    const KeyPosture& key = keys[i];
    std::string problem;
    if (!std::isfinite(key.time)) {
      problem = "time is not finite";
    } else if (i > 0 && !(key.time > keys[i - 1].time)) {
      problem = cat("time ", shortest(key.time), " is not after the previous key's ", shortest(keys[i - 1].time));
    } else if (key.values.size() != keys[0].values.size()) {
      problem =
          cat("has ", std::to_string(key.values.size()), " values, key 0 has ", std::to_string(keys[0].values.size()));
    } else if (!std::all_of(key.values.begin(), key.values.end(), [](double v) { return std::isfinite(v); })) {
      problem = "a value is not finite";
    } else if (!in_unit_range(key.tension) || !in_unit_range(key.continuity) || !in_unit_range(key.bias)) {
      problem = "tension, continuity and bias must each lie in [-1, 1]";
    }
    if (!problem.empty()) {
      *error = key_error(i, problem);
      return false;
    }
  }
  return true;
}

}  // namespace

// Kochanek & Bartels (1984), with t, c, b the tension, continuity and bias of
// key i and P its values:
//   outgoing_i = (1-t)(1+c)(1+b)/2 (P_i - P_i-1) + (1-t)(1-c)(1-b)/2 (P_i+1 - P_i)
//   incoming_i = (1-t)(1-c)(1+b)/2 (P_i - P_i-1) + (1-t)(1+c)(1-b)/2 (P_i+1 - P_i)
// Keys need not be evenly spaced in time, so, as the paper prescribes for
// uneven steps, each tangent is scaled to its segment's length: the outgoing
// one by 2 dt_i / (dt_i-1 + dt_i), the incoming one by 2 dt_i-1 / (dt_i-1 + dt_i);
// with c = 0 the velocity is then continuous across the key. At the first and
// last key the missing chord is taken equal to the existing one (a phantom key
// mirrored through the end key, with the same spacing).
bool KbSpline::create(std::vector<KeyPosture> keys, KbSpline* out, std::string* error) {
  if (!validate(keys, error)) return false;
  KbSpline spline;
  spline.dimension_ = keys[0].values.size();
  const size_t n = keys.size();
  const size_t dim = spline.dimension_;
  spline.outgoing_.assign(n * dim, 0.0);
  spline.incoming_.assign(n * dim, 0.0);
  for (size_t i = 0; i < n && n > 1; ++i) {
    const KeyPosture& key = keys[i];
    const bool first = i == 0;
    const bool last = i + 1 == n;
    const double dt_after = last ? keys[i].time - keys[i - 1].time : keys[i + 1].time - keys[i].time;
    const double dt_before = first ? dt_after : keys[i].time - keys[i - 1].time;
    const double t = key.tension, c = key.continuity, b = key.bias;
    const double out_before = (1 - t) * (1 + c) * (1 + b) / 2;
    const double out_after = (1 - t) * (1 - c) * (1 - b) / 2;
    const double in_before = (1 - t) * (1 - c) * (1 + b) / 2;
    const double in_after = (1 - t) * (1 + c) * (1 - b) / 2;
    const double out_scale = 2 * dt_after / (dt_before + dt_after);
    const double in_scale = 2 * dt_before / (dt_before + dt_after);
    for (size_t d = 0; d < dim; ++d) {
      const double chord_after = last ? key.values[d] - keys[i - 1].values[d] : keys[i + 1].values[d] - key.values[d];
      const double chord_before = first ? chord_after : key.values[d] - keys[i - 1].values[d];
      spline.outgoing_[i * dim + d] = out_scale * (out_before * chord_before + out_after * chord_after);
      spline.incoming_[i * dim + d] = in_scale * (in_before * chord_before + in_after * chord_after);
    }
  }
  spline.keys_ = std::move(keys);
  *out = std::move(spline);
  return true;
}

void KbSpline::sample(double time, std::span<double> out) const {
  if (out.size() != dimension_)
    throw std::invalid_argument(cat("KbSpline::sample: output has ", std::to_string(out.size()), " elements, expected ",
                                    std::to_string(dimension_)));
  if (keys_.empty()) throw std::logic_error("KbSpline::sample on a spline without keys (use create)");
  const auto copy_key = [&](size_t i) { std::copy(keys_[i].values.begin(), keys_[i].values.end(), out.begin()); };
  if (!(time > keys_.front().time)) {  // also NaN
    copy_key(0);
    return;
  }
  if (!(time < keys_.back().time)) {
    copy_key(keys_.size() - 1);
    return;
  }
  const auto after_it =
      std::upper_bound(keys_.begin(), keys_.end(), time, [](double t, const KeyPosture& key) { return t < key.time; });
  const auto next = static_cast<size_t>(after_it - keys_.begin());
  const size_t i = next - 1;
  const double s = (time - keys_[i].time) / (keys_[next].time - keys_[i].time);
  // Cubic Hermite basis.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1;
  const double h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2;
  const double h11 = s3 - s2;
  for (size_t d = 0; d < dimension_; ++d) {
    out[d] = h00 * keys_[i].values[d] + h10 * outgoing_[i * dimension_ + d] + h01 * keys_[next].values[d] +
             h11 * incoming_[next * dimension_ + d];
  }
}

std::vector<double> KbSpline::sample(double time) const {
  std::vector<double> out(dimension_);
  sample(time, out);
  return out;
}

std::span<const double> KbSpline::outgoing_tangent(size_t key) const {
  if (key >= keys_.size()) throw std::out_of_range(cat("KbSpline key ", std::to_string(key)));
  return std::span<const double>(outgoing_).subspan(key * dimension_, dimension_);
}

std::span<const double> KbSpline::incoming_tangent(size_t key) const {
  if (key >= keys_.size()) throw std::out_of_range(cat("KbSpline key ", std::to_string(key)));
  return std::span<const double>(incoming_).subspan(key * dimension_, dimension_);
}

}  // namespace sinew::motion
