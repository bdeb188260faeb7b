#include "signal_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sinew::hal::can {

namespace {

uint64_t key_of(uint32_t id, bool extended) { return (static_cast<uint64_t>(extended) << 32) | id; }

bool fail(std::string* error, const SignalSpec& s, const char* what) {
  if (error != nullptr) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "signal for input %u on 0x%X: %s", unsigned{s.input}, s.can_id, what);
    *error = buf;
  }
  return false;
}

// Largest |raw| the field can hold, as a double.
double raw_magnitude_limit(const SignalSpec& s) { return std::ldexp(1.0, s.length - (s.is_signed ? 1 : 0)); }

}  // namespace

bool validate(const SignalSpec& s, std::string* error) {
  if (s.length < 1 || s.length > 64) return fail(error, s, "length must be 1..64");
  const uint32_t mask = s.extended ? 0x1FFFFFFFu : 0x7FFu;
  if ((s.can_id & ~mask) != 0) return fail(error, s, "identifier does not fit its format");
  if (bytes_needed(s.start_bit, s.length, s.byte_order) == 0) return fail(error, s, "signal does not fit in 64 bytes");
  if (!std::isfinite(s.scale) || s.scale == 0.0 || !std::isfinite(s.offset)) {
    return fail(error, s, "scale must be finite and non-zero, offset finite");
  }
  // Every raw value maps to a finite physical value: |raw| < 2^64, so bounding
  // |scale| x 2^64 + |offset| bounds them all. NaN cannot arise from finite
  // products and sums of finite numbers that do not overflow.
  if (!std::isfinite(std::fabs(s.scale) * raw_magnitude_limit(s) + std::fabs(s.offset))) {
    return fail(error, s, "scale x raw range overflows a double");
  }
  if (!std::isfinite(s.min) || !std::isfinite(s.max) || s.min > s.max)
    return fail(error, s, "range must be finite with min <= max");
  if (s.min == 0.0 && s.max == 0.0)
    return fail(error, s, "range [0|0] (DBC's 'unbounded') is refused: give the joint's limits");
  if (s.unit == PhysicalUnit::kRigUnits) {
    int32_t probe = 0;
    if (!to_engine_value(s.min, s.unit, probe) || !to_engine_value(s.max, s.unit, probe)) {
      return fail(error, s, "range exceeds Q12.20 rig units (+-2048)");
    }
  }
  return true;
}

double physical_value(const SignalSpec& s, uint64_t raw) {
  const double r = s.is_signed ? static_cast<double>(sign_extend(raw, s.length)) : static_cast<double>(raw);
  return r * s.scale + s.offset;
}

bool SignalDecoder::configure(const std::vector<SignalSpec>& signals, std::string* error) {
  std::vector<Entry> entries;
  std::vector<uint16_t> inputs;
  for (const SignalSpec& s : signals) {
    if (!validate(s, error)) return false;
    entries.push_back({key_of(s.can_id, s.extended), s, bytes_needed(s.start_bit, s.length, s.byte_order)});
    inputs.push_back(s.input);
  }
  if (entries.empty()) {
    if (error != nullptr) *error = "signal decoder: no signals configured";
    return false;
  }
  std::sort(inputs.begin(), inputs.end());
  if (std::adjacent_find(inputs.begin(), inputs.end()) != inputs.end()) {
    if (error != nullptr) *error = "signal decoder: an input is fed by two signals";
    return false;
  }
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  for (size_t i = 0, run = 0; i < entries.size(); ++i) {
    run = (i > 0 && entries[i].key == entries[i - 1].key) ? run + 1 : 1;
    if (run > kMaxSamplesPerFrame) {
      if (error != nullptr) *error = "signal decoder: more than 32 signals on one identifier";
      return false;
    }
  }
  entries_ = std::move(entries);
  channel_info_.clear();
  frame_ids_.clear();
  wants_fd_ = false;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const SignalSpec& s = entries_[i].spec;
    const uint64_t timeout = s.timeout_ns != 0 ? s.timeout_ns : s.period_ns + s.period_ns / 2;
    channel_info_.push_back({s.input, timeout});
    if (i == 0 || entries_[i].key != entries_[i - 1].key) frame_ids_.push_back({s.can_id, s.extended});
    wants_fd_ = wants_fd_ || entries_[i].bytes > 8;
  }
  size_counters(channel_info_);
  return true;
}

void SignalDecoder::decode_frame(const CanFrame& frame, FrameDecode& out) {
  const uint64_t key = key_of(frame.id, frame.extended);
  auto it =
      std::lower_bound(entries_.begin(), entries_.end(), key, [](const Entry& e, uint64_t k) { return e.key < k; });
  if (it == entries_.end() || it->key != key) {
    out.add_rejection(kNoInput, RejectReason::kUnknownId);
    return;
  }
  const std::span<const uint8_t> payload(frame.data.data(), frame.len);
  for (; it != entries_.end() && it->key == key; ++it) {
    const SignalSpec& s = it->spec;
    const auto input = static_cast<int32_t>(s.input);
    if (frame.kind != FrameKind::kData || frame.len < it->bytes) {
      out.add_rejection(input, RejectReason::kMalformed);
      continue;
    }
    const double physical = physical_value(s, extract_bits(payload, s.start_bit, s.length, s.byte_order));
    int32_t value = 0;
    if (!(physical >= s.min && physical <= s.max) || !to_engine_value(physical, s.unit, value)) {
      out.add_rejection(input, RejectReason::kOutOfRange);
      continue;
    }
    out.add_sample({s.input, value, frame.timestamp_ns, kSampleOk});
  }
}

}  // namespace sinew::hal::can
