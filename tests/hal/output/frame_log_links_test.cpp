// The frame log in a directory another user can write to: links planted at
// the log's name or at its old temporary name never redirect a write, and a
// world-writable directory without the sticky bit is refused.
#include <sys/stat.h>
#include <unistd.h>

#include "frame_log_fixture.hpp"
#include "tests/support/planted_links.hpp"

namespace sinew::test {
namespace {

using hal::output::FrameLogWriter;

bool log_error_has(const std::string& error, const std::string& part) { return error.find(part) != std::string::npos; }

// An empty victim: the writer gives an empty file a header, so following the
// link would have written one into the victim.
TEST_F(FrameLogTest, NeverFollowsALinkPlantedAtTheLogsName) {
  const LinkTrap trap("");
  trap.plant_symlink("a.log");
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(trap.out("a.log"), shape_, {}, &error));
  EXPECT_TRUE(log_error_has(error, "frame log " + trap.out("a.log") + ": is a symbolic link, refusing to follow it"))
      << error;
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_TRUE(trap.is_symlink("a.log"));
}

// The old writer truncated "<path>.tmp" through the link, wrote the header
// into the victim, and renamed the link into place.
TEST_F(FrameLogTest, NeverFollowsALinkPlantedAtTheOldTemporaryName) {
  const LinkTrap trap;
  trap.plant_symlink("a.log.tmp");
  const std::string path = trap.out("a.log");
  write_frames(path, 0, kFrames);
  EXPECT_TRUE(trap.victim_untouched());
  EXPECT_TRUE(trap.is_symlink("a.log.tmp"));
  EXPECT_FALSE(trap.is_symlink("a.log"));
  const ReadBack r = read_log(path);
  ASSERT_TRUE(r.opened) << r.error;
  expect_frames(r.poses, kFrames);
  EXPECT_EQ(trap.out_entries(), 2u);  // the log and the planted link: no temporary file left
}

// Anyone could rename another file over the log between the writer's steps.
TEST_F(FrameLogTest, RefusesAWorldWritableDirectoryWithoutTheStickyBit) {
  const LinkTrap trap;
  trap.set_out_dir_mode(0777);
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(trap.out("a.log"), shape_, {}, &error));
  EXPECT_TRUE(log_error_has(error, "directory " + trap.out_dir() + " is writable by every user and has no sticky bit"))
      << error;
  EXPECT_EQ(trap.out_entries(), 0u);

  // With the sticky bit (as /tmp has) only a file's owner may rename or remove it.
  trap.set_out_dir_mode(01777);
  write_frames(trap.out("a.log"), 0, kFrames);
  expect_frames(read_log(trap.out("a.log")).poses, kFrames);
}

// A hard link to a log elsewhere: appending would change that other file.
TEST_F(FrameLogTest, RefusesALogWithASecondName) {
  const LinkTrap trap("");  // empty: the writer makes it a log
  write_frames(trap.victim(), 0, 2);
  const std::string before = LinkTrap::read_whole(trap.victim());
  trap.plant_hard_link("a.log");
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(trap.out("a.log"), shape_, {}, &error));
  EXPECT_TRUE(log_error_has(error, "has 2 names (hard links)")) << error;
  EXPECT_EQ(LinkTrap::read_whole(trap.victim()), before);
}

// In a shared directory, a log another user left (or planted) there is theirs.
TEST_F(FrameLogTest, RefusesAnotherUsersLogInASharedDirectory) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give a file to another user";
  const LinkTrap trap;
  trap.set_out_dir_mode(01777);
  const std::string path = trap.out("a.log");
  write_frames(path, 0, 2);
  ASSERT_EQ(::chown(path.c_str(), 65534, 65534), 0);
  const std::string before = LinkTrap::read_whole(path);
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(path, shape_, {}, &error));
  EXPECT_TRUE(log_error_has(error, "belongs to uid 65534")) << error;
  EXPECT_EQ(LinkTrap::read_whole(path), before);
}

}  // namespace
}  // namespace sinew::test
