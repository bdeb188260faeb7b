// sinew-receive's CSV file in a directory another user can write to: a link
// planted at its name is refused, an existing file is replaced by a new one
// (never truncated in place, which would empty its other names too), and a
// world-writable directory without the sticky bit is refused.
#include <string>

#include "host_tools/receiver/csv_writer.hpp"
#include "tests/support/planted_links.hpp"

namespace sinew::test {
namespace {

using receiver::CsvWriter;

bool csv_error_has(const std::string& error, const std::string& part) { return error.find(part) != std::string::npos; }

TEST(CsvWriterLinks, NeverFollowsALinkPlantedAtItsName) {
  const LinkTrap trap;
  trap.plant_symlink("frames.csv");
  CsvWriter csv;
  std::string error;
  EXPECT_FALSE(csv.open(trap.out("frames.csv"), false, &error));
  EXPECT_TRUE(
      csv_error_has(error, "CSV file " + trap.out("frames.csv") + ": is a symbolic link, refusing to follow it"))
      << error;
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_TRUE(trap.is_symlink("frames.csv"));
}

TEST(CsvWriterLinks, ReplacesAFileWithASecondNameWithoutEmptyingTheOther) {
  const LinkTrap trap;
  trap.plant_hard_link("frames.csv");
  CsvWriter csv;
  std::string error;
  ASSERT_TRUE(csv.open(trap.out("frames.csv"), false, &error)) << error;
  EXPECT_TRUE(csv.close());
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_EQ(LinkTrap::read_whole(trap.out("frames.csv")), "");  // a new, empty file
  EXPECT_EQ(trap.out_entries(), 1u);
}

TEST(CsvWriterLinks, RefusesAWorldWritableDirectoryWithoutTheStickyBit) {
  const LinkTrap trap;
  trap.set_out_dir_mode(0777);
  CsvWriter csv;
  std::string error;
  EXPECT_FALSE(csv.open(trap.out("frames.csv"), false, &error));
  EXPECT_TRUE(csv_error_has(error, "directory " + trap.out_dir() + " is writable by every user and has no sticky bit"))
      << error;
  EXPECT_EQ(trap.out_entries(), 0u);

  trap.set_out_dir_mode(01777);
  EXPECT_TRUE(csv.open(trap.out("frames.csv"), false, &error)) << error;
  EXPECT_TRUE(csv.close());
  EXPECT_EQ(trap.out_entries(), 1u);
}

}  // namespace
}  // namespace sinew::test
