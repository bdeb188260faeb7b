#include "text_file.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "text_scan.hpp"

namespace sinew::motion {

bool read_text_file(const std::string& path, std::string* text, std::string* error) {
  // stdio rather than iostreams: simple, and free of GCC's false null-dereference warnings in <streambuf>.
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) {
    *error = cat(path, ": cannot open: ", std::strerror(errno));
    return false;
  }
  text->clear();
  std::array<char, 1 << 16> buffer{};
  size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), file.get())) > 0) text->append(buffer.data(), got);
  if (std::ferror(file.get())) {
    *error = cat(path, ": read error");
    return false;
  }
  return true;
}

}  // namespace sinew::motion
