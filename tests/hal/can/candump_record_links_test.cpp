// A candump `record` file in a directory another user can write to: a link
// planted at its name is refused, an existing file is replaced by a new one
// (never truncated in place, which would empty its other names too), and a
// world-writable directory without the sticky bit is refused.
#include <gtest/gtest.h>

#include <string>

#include "hal/can/candump_format.hpp"
#include "hal/can/candump_writer.hpp"
#include "tests/support/planted_links.hpp"

namespace sinew::hal::can {
namespace {

using test::LinkTrap;

bool record_error_has(const std::string& error, const std::string& part) {
  return error.find(part) != std::string::npos;
}

CanFrame record_frame() {
  CanFrame f;
  f.id = 0x123;
  f.timestamp_ns = 1'000'000'000u;
  f.data[f.len++] = 0x42;
  return f;
}

TEST(CandumpRecordLinks, NeverFollowsALinkPlantedAtItsName) {
  const LinkTrap trap;
  trap.plant_symlink("in.candump");
  CandumpWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(trap.out("in.candump"), &error));
  EXPECT_TRUE(record_error_has(
      error, "candump record " + trap.out("in.candump") + ": is a symbolic link, refusing to follow it"))
      << error;
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_TRUE(trap.is_symlink("in.candump"));
}

TEST(CandumpRecordLinks, ReplacesAFileWithASecondNameWithoutEmptyingTheOther) {
  const LinkTrap trap;
  trap.plant_hard_link("in.candump");
  CandumpWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(trap.out("in.candump"), &error)) << error;
  ASSERT_TRUE(writer.write(record_frame(), "can0"));
  ASSERT_TRUE(writer.flush());
  writer.close();
  EXPECT_TRUE(trap.victim_untouched());
  CandumpLog log;
  ASSERT_TRUE(read_candump_file(trap.out("in.candump"), log, &error)) << error;
  EXPECT_EQ(log.frames.size(), 1u);
  EXPECT_EQ(trap.out_entries(), 1u);
}

TEST(CandumpRecordLinks, RefusesAWorldWritableDirectoryWithoutTheStickyBit) {
  const LinkTrap trap;
  trap.set_out_dir_mode(0777);
  CandumpWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(trap.out("in.candump"), &error));
  EXPECT_TRUE(
      record_error_has(error, "directory " + trap.out_dir() + " is writable by every user and has no sticky bit"))
      << error;
  EXPECT_EQ(trap.out_entries(), 0u);

  trap.set_out_dir_mode(01777);
  EXPECT_TRUE(writer.open(trap.out("in.candump"), &error)) << error;
  writer.close();
  EXPECT_EQ(trap.out_entries(), 1u);
}

}  // namespace
}  // namespace sinew::hal::can
