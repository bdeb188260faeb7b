#include "parse_number.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "text_scan.hpp"

namespace sinew::motion {

bool parse_finite_double(std::string_view token, double* out, std::string* why) {
  std::string_view digits = token;
  // from_chars refuses a leading '+', which some exporters write.
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+') digits.remove_prefix(1);
  double value = 0;
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, value, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) {
    *why = cat(quoted(token), " is out of range for a double");
    return false;
  }
  if (ec != std::errc() || ptr != end || digits.empty()) {
    *why = cat(quoted(token), " is not a number");
    return false;
  }
  if (!std::isfinite(value)) {
    *why = cat(quoted(token), " is not a finite number");
    return false;
  }
  *out = value;
  return true;
}

bool parse_count(std::string_view token, size_t* out, std::string* why) {
  size_t value = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc::result_out_of_range) {
    *why = cat(quoted(token), " is too large");
    return false;
  }
  if (ec != std::errc() || ptr != end || token.empty()) {
    *why = cat(quoted(token), " is not a non-negative integer");
    return false;
  }
  *out = value;
  return true;
}

}  // namespace sinew::motion
