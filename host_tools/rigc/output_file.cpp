#include "output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

namespace sinew::rigc {
namespace {

bool write_all(std::FILE* f, std::string_view bytes) {
  return bytes.empty() || std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
}

}  // namespace

bool write_output_file(const std::string& path, std::string_view bytes, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    if (fs::is_directory(st)) return *error = "cannot write " + path + ": it is a directory", false;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return *error = "cannot write " + path + ": " + std::strerror(errno), false;
    bool ok = write_all(f, bytes);
    int saved = ok ? 0 : errno;
    if (std::fclose(f) != 0 && ok) {
      ok = false;
      saved = errno;
    }
    if (!ok) return *error = "cannot write " + path + ": " + std::strerror(saved), false;
    return true;
  }
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string tmpl = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0) return *error = "cannot write " + path + ": " + std::strerror(errno), false;
  const std::string tmp(name.data());
  // mkstemp creates the file 0600; give it what a plain open would have.
  const mode_t mask = umask(0);
  umask(mask);
  (void)fchmod(fd, 0666 & ~mask);
  std::FILE* f = fdopen(fd, "wb");
  if (f == nullptr) {
    const int saved = errno;
    close(fd);
    std::remove(tmp.c_str());
    return *error = "cannot write " + path + ": " + std::strerror(saved), false;
  }
  bool ok = write_all(f, bytes) && std::fflush(f) == 0 && fsync(fileno(f)) == 0;
  int saved = ok ? 0 : errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    saved = errno;
  }
  if (ok && std::rename(tmp.c_str(), path.c_str()) != 0) {
    ok = false;
    saved = errno;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    return *error = "cannot write " + path + ": " + std::strerror(saved), false;
  }
  return true;
}

}  // namespace sinew::rigc
