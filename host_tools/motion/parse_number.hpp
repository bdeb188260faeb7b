// Strict, locale-independent number parsing for motion files: the whole token
// must be the number, and NaN or infinity are refused (a non-finite angle
// would poison every pose computed from it).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace sinew::motion {

// Parses a finite double ("12", "-0.5", ".0083", "1e-3", "+2"). On failure
// returns false and sets `why` to a short reason naming the token.
bool parse_finite_double(std::string_view token, double* out, std::string* why);

// Parses a non-negative decimal integer that fits in size_t.
bool parse_count(std::string_view token, size_t* out, std::string* why);

}  // namespace sinew::motion
