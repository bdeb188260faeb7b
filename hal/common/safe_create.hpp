// Creating and opening output files so that nobody else can redirect the
// writes. sinewd may run as root with its files in a directory other users
// can write to (/tmp); a symbolic link planted there under the file's name, or
// under the name of its temporary file, must not make it write to the file
// the link points at.
//
// The rules, the same for every file the project writes:
//  - The directory part of the path is resolved once (symbolic links in it
//    are followed: the directory is the caller's choice) and everything after
//    that happens relative to that directory's descriptor (openat, renameat).
//  - A directory anyone may write to is refused unless it has the sticky bit:
//    without it, anyone could rename or replace the file under the writer.
//  - A symbolic link at the file's own name is never followed: it is refused.
//  - A new file is first created under a fresh, unpredictable temporary name
//    with O_CREAT|O_EXCL|O_NOFOLLOW (which fails rather than open anything
//    that is already there), then moved into place with renameat(), which
//    replaces the directory entry at the final name and never writes through
//    it.
//  - An existing file that is replaced or written in place must be a regular
//    file and, in a world-writable directory, belong to this process's user
//    or to the directory's owner (the kernel's protected_regular rule); one
//    written in place (a frame log being appended to) must also have no other
//    name (hard link).
//
// Messages name the file and the problem: "<what> <path>: <problem>", e.g.
// "frame log x.log: is a symbolic link, refusing to follow it".
#pragma once

#include <sys/stat.h>  // mode_t, struct stat

#include <string>
#include <string_view>

namespace sinew::hal {

// The directory that holds one output file, opened and checked, and the
// steps of creating or opening that file relative to it.
class OutputDir {
 public:
  OutputDir() = default;
  ~OutputDir();  // removes a temporary file that was not committed
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  // Opens the directory holding `path` and refuses one that is world-writable
  // without the sticky bit, or a path that names no file (ends in '/', ".").
  // `what` names the file in every message ("frame log").
  bool open(const std::string& path, std::string_view what, std::string* error);

  // Opens the file at the path as it is (no O_CREAT), with `flags` (e.g.
  // O_RDWR) plus O_NOFOLLOW|O_CLOEXEC|O_NOCTTY. No file there: -1 with
  // *missing set and no message. Refused with a message (-1): a symbolic
  // link, anything but a regular file, a file with more than one name, a
  // file of another user in a world-writable directory.
  int open_existing(int flags, bool* missing, std::string* error);

  // True if the path may be replaced: nothing there, or a regular file
  // (other names of it keep the old contents). Refuses, with a message, a
  // symbolic link, a directory or another kind of file, and a file of another
  // user in a world-writable directory.
  bool check_replaceable(std::string* error);

  // Creates an empty file, open read-write, under a fresh temporary name in
  // the directory (".<name>.<random>.tmp", O_CREAT|O_EXCL|O_NOFOLLOW, `mode`
  // less the umask). One temporary file at a time.
  int create_temp(mode_t mode, std::string* error);

  // Renames the temporary file to the path (renameat: an entry already there
  // is replaced, never written through), then syncs the directory so the new
  // entry survives a power cut.
  bool commit(std::string* error);

  // Removes the temporary file, if one was created and not committed.
  void discard();

  int fd() const { return dir_fd_; }
  const std::string& path() const { return path_; }
  // "<what> <path>", the start of every message about the file.
  std::string subject() const;

 private:
  bool check_existing(const struct stat& st, bool in_place, std::string* error) const;
  std::string refuse(const std::string& problem) const;

  int dir_fd_ = -1;
  bool dir_world_writable_ = false;  // sticky: open() refuses it otherwise
  uid_t dir_owner_ = 0;
  std::string what_;
  std::string path_;
  std::string dir_;
  std::string name_;  // the final component, created relative to dir_fd_
  std::string temp_;  // the temporary file's name while it exists
};

// Creates the file at `path` anew and empty, replacing a regular file there
// (never writing through a link), and returns a descriptor open read-write;
// -1 with a message otherwise. For files written as they go (a candump
// record, a CSV stream).
int create_replacing(const std::string& path, std::string_view what, mode_t mode, std::string* error);

// Writes `bytes` to `path` whole or not at all: into a temporary file, synced,
// then renamed over the path. False with a message; nothing is left behind.
bool write_replacing(const std::string& path, std::string_view what, std::string_view bytes, mode_t mode,
                     std::string* error);

}  // namespace sinew::hal
