// rigc's and sinew-pose's output file in a directory another user can write
// to: a link planted at its name is refused rather than replaced or written
// through, a world-writable directory without the sticky bit is refused, and
// devices such as /dev/null are still written where they are.
#include <gtest/gtest.h>

#include <string>

#include "host_tools/rigc/output_file.hpp"
#include "tests/support/planted_links.hpp"

namespace sinew::test {
namespace {

bool output_error_has(const std::string& error, const std::string& part) {
  return error.find(part) != std::string::npos;
}

TEST(OutputFileLinks, NeverFollowsALinkPlantedAtItsName) {
  const LinkTrap trap;
  trap.plant_symlink("out.rig");
  std::string error;
  EXPECT_FALSE(rigc::write_output_file(trap.out("out.rig"), "new bytes", &error));
  EXPECT_TRUE(
      output_error_has(error, "output file " + trap.out("out.rig") + ": is a symbolic link, refusing to follow it"))
      << error;
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_TRUE(trap.is_symlink("out.rig"));
  EXPECT_EQ(trap.out_entries(), 1u);  // the link only: no temporary file left
}

TEST(OutputFileLinks, RefusesAWorldWritableDirectoryWithoutTheStickyBit) {
  const LinkTrap trap;
  trap.set_out_dir_mode(0777);
  std::string error;
  EXPECT_FALSE(rigc::write_output_file(trap.out("out.rig"), "new bytes", &error));
  EXPECT_TRUE(
      output_error_has(error, "directory " + trap.out_dir() + " is writable by every user and has no sticky bit"))
      << error;
  EXPECT_EQ(trap.out_entries(), 0u);

  trap.set_out_dir_mode(01777);
  ASSERT_TRUE(rigc::write_output_file(trap.out("out.rig"), "new bytes", &error)) << error;
  EXPECT_EQ(LinkTrap::read_whole(trap.out("out.rig")), "new bytes");
  EXPECT_TRUE(rigc::write_output_file("/dev/null", "new bytes", &error)) << error;
}

}  // namespace
}  // namespace sinew::test
