#include "privileges.hpp"

#include <grp.h>
#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace sinew::firmware {

namespace {

struct Identity {
  uid_t uid = 0;
  gid_t gid = 0;
};

bool look_up(const std::string& user, const std::string& what, Identity* id, std::string* error) {
  std::vector<char> buffer(16384);
  passwd entry{};
  passwd* found = nullptr;
  const int rc = getpwnam_r(user.c_str(), &entry, buffer.data(), buffer.size(), &found);
  if (rc != 0 || found == nullptr)
    return *error = what + ": no such user" + (rc != 0 ? std::string(" (") + std::strerror(rc) + ")" : ""), false;
  *id = {entry.pw_uid, entry.pw_gid};
  return true;
}

bool already(const Identity& id) { return geteuid() == id.uid && getuid() == id.uid; }

}  // namespace

bool can_drop_privileges(const std::string& user, std::string* error) {
  const std::string what = "[realtime] user = \"" + user + "\"";
  Identity id;
  if (!look_up(user, what, &id, error)) return false;
  if (geteuid() == 0 || already(id)) return true;
  return *error = what + ": sinewd runs as uid " + std::to_string(geteuid()) +
                  ", not root, and cannot become another user (start it as root, or as " + user + ")",
         false;
}

bool drop_privileges(const std::string& user, std::string* report, std::string* error) {
  const std::string what = "[realtime] user = \"" + user + "\"";
  if (!can_drop_privileges(user, error)) return false;
  Identity id;
  if (!look_up(user, what, &id, error)) return false;
  const uid_t uid = id.uid;
  const gid_t gid = id.gid;
  const std::string ids = " (uid " + std::to_string(uid) + ", gid " + std::to_string(gid) + ")";
  if (geteuid() != 0) {
    *report = "sinewd: running as user " + user + ids + " already\n";
    return true;
  }
  if (initgroups(user.c_str(), gid) != 0) return *error = what + ": initgroups: " + std::strerror(errno), false;
  if (setgid(gid) != 0) return *error = what + ": setgid: " + std::strerror(errno), false;
  if (setuid(uid) != 0) return *error = what + ": setuid: " + std::strerror(errno), false;
  // Irreversible, unless the user is root itself.
  if (uid != 0 && (setuid(0) == 0 || seteuid(0) == 0))
    return *error = what + ": root could be regained after setuid; refusing to run", false;
  *report = "sinewd: running as user " + user + ids + " from here on (devices, sockets and files opened as root)\n";
  return true;
}

}  // namespace sinew::firmware
