// Reads a whole file into memory for the text parsers.
#pragma once

#include <string>

namespace sinew::motion {

// On failure returns false and sets `error` to "<path>: <reason>".
bool read_text_file(const std::string& path, std::string* text, std::string* error);

}  // namespace sinew::motion
