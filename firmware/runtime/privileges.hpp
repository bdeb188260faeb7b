// [realtime] user: sinewd started as root opens its devices, sockets and
// files and applies its real-time settings (SCHED_FIFO, affinity, mlockall)
// as root, then runs as this user for the rest of its life: the tick, the
// I/O threads and every later file operation hold no privilege a bug could
// use. Every thread changes identity together (glibc's setuid applies to
// the whole process), and the change is checked to be irreversible.
#pragma once

#include <string>

namespace sinew::firmware {

// Switches the process to `user`'s uid, gid and supplementary groups. Not
// root: fine (report says so) when already that user, else false. False
// with `error` naming the user and the failing call.
bool drop_privileges(const std::string& user, std::string* report, std::string* error);

// Whether drop_privileges could succeed (the user exists; sinewd is root or
// already that user), checked before anything is opened. False with `error`.
bool can_drop_privileges(const std::string& user, std::string* error);

}  // namespace sinew::firmware
