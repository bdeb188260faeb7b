// Reads a binary file (a compiled rig) whole into 8-byte aligned memory,
// the one place the daemon, the tools, the benches and the tests load blob
// files. Only regular files are read (a FIFO or a device could block or never
// end), and only up to max_bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sinew::hal {

struct BlobBytes {
  std::vector<uint64_t> words;  // the bytes, 8-byte aligned, zero padded
  size_t size = 0;
  const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(words.data()); }
};

// A check of a file's first bytes against its size, run before the rest is
// read (a 1 GB file that is not a blob costs one small read, not 1 GB).
// False with a message (the path is prefixed by the caller).
struct PrefixCheck {
  size_t bytes = 0;  // how many leading bytes `check` needs; 0: no check
  bool (*check)(const uint8_t* head, size_t head_bytes, uint64_t file_bytes, std::string* error) = nullptr;
};

// False with a message naming the path and the problem.
bool read_blob_file(const std::string& path, size_t max_bytes, BlobBytes* out, std::string* error,
                    PrefixCheck prefix = {});

// Copies `size` bytes into aligned memory.
BlobBytes blob_from_bytes(const uint8_t* bytes, size_t size);

}  // namespace sinew::hal
