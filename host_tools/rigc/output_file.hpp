// Writes a whole output file or nothing: the bytes go to a temporary file next
// to `path`, which is checked after close and renamed over `path` only then.
// Paths that exist and are not regular files (/dev/stdout, /dev/full, a FIFO)
// are written in place, and a failed write is still reported.
#pragma once

#include <string>
#include <string_view>

namespace sinew::rigc {

// Returns false with a message naming `path` (nothing left behind in a
// regular directory).
bool write_output_file(const std::string& path, std::string_view bytes, std::string* error);

}  // namespace sinew::rigc
