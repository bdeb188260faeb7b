// What another user of a shared directory can do to a program's output
// files, for the tests of every writer: plant a symbolic link (or a hard
// link) under the name the writer will use, pointing at a victim file that
// lies outside the output directory, and make the directory world-writable.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>

namespace sinew::test {

class LinkTrap {
 public:
  // The victim holds `victim_bytes` (empty: an empty file, which a writer
  // that adopts empty files would otherwise write into).
  explicit LinkTrap(std::string victim_bytes = "bytes another user must not lose\n")
      : victim_bytes_(std::move(victim_bytes)) {
    std::string pattern = testing::TempDir() + "sinew_links_XXXXXX";
    if (::mkdtemp(pattern.data()) != nullptr) root_ = pattern;
    EXPECT_FALSE(root_.empty()) << "mkdtemp failed";
    std::filesystem::create_directory(out_dir());
    write_whole(victim(), victim_bytes_);
  }
  ~LinkTrap() {
    std::error_code ec;
    if (!root_.empty()) std::filesystem::remove_all(root_, ec);
  }
  LinkTrap(const LinkTrap&) = delete;
  LinkTrap& operator=(const LinkTrap&) = delete;

  // The directory the writer writes into, and a name in it.
  std::string out_dir() const { return root_ + "/out"; }
  std::string out(const std::string& name) const { return out_dir() + "/" + name; }
  // The file the planted links point at, outside the output directory.
  std::string victim() const { return root_ + "/victim"; }

  void plant_symlink(const std::string& name) const {
    ASSERT_EQ(::symlink(victim().c_str(), out(name).c_str()), 0) << out(name);
  }
  void plant_hard_link(const std::string& name) const {
    ASSERT_EQ(::link(victim().c_str(), out(name).c_str()), 0) << out(name);
  }
  void set_out_dir_mode(mode_t mode) const { ASSERT_EQ(::chmod(out_dir().c_str(), mode), 0); }

  bool victim_untouched() const { return read_whole(victim()) == victim_bytes_; }
  bool is_symlink(const std::string& name) const {
    return std::filesystem::is_symlink(std::filesystem::symlink_status(out(name)));
  }
  // How many entries the output directory holds: no temporary file may be left behind.
  size_t out_entries() const {
    std::error_code ec;
    return static_cast<size_t>(
        std::distance(std::filesystem::directory_iterator(out_dir(), ec), std::filesystem::directory_iterator()));
  }

  static std::string read_whole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;  // not istreambuf_iterator: gcc 12 -O3 reports a false null dereference there
    bytes << in.rdbuf();
    return bytes.str();
  }
  static void write_whole(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  }

 private:
  std::string victim_bytes_;
  std::string root_;
};

}  // namespace sinew::test
