// Writes a whole output file or nothing: the bytes go to a fresh temporary
// file next to `path`, which is synced and renamed over `path` only then
// (hal/common/safe_create.hpp: a symbolic link at the path is refused, never
// followed, and so is a world-writable directory without the sticky bit).
// A character device or FIFO at the path (/dev/full, /dev/null, a pipe) is
// written in place, and a failed write is still reported.
#pragma once

#include <string>
#include <string_view>

namespace sinew::rigc {

// Returns false with a message naming `path` (nothing left behind in a
// regular directory).
bool write_output_file(const std::string& path, std::string_view bytes, std::string* error);

}  // namespace sinew::rigc
