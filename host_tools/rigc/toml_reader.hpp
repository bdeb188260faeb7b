// Reading the keys of a TOML rig spec's tables: each reader leaves the value
// alone when the key is absent, refuses a wrong type or range with
// "file:line: [table] key must be ...", and returns false. Used by the core
// spec (toml_spec.cpp) and every layer's table (tables/<layer>_table.cpp).
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <string>

#include "host_tools/layers/common/layer_compile.hpp"

namespace sinew::rigc::spec_read {

// "file:line: key", the prefix of every message about a node.
std::string at(const std::string& path, const toml::node* n, const std::string& key);

// Refuses keys a table does not know (a typo would otherwise fall back to a default).
bool known_keys(const std::string& path, const toml::table& t, const std::string& table,
                std::initializer_list<const char*> keys, std::string* error);

bool read_number(const std::string& path, const toml::table& t, const std::string& table, const char* key, double* out,
                 std::string* error);

template <typename Int>
bool read_int(const std::string& path, const toml::table& t, const std::string& table, const char* key, int64_t lo,
              int64_t hi, Int* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<int64_t>();
  if (!v || *v < lo || *v > hi)
    return *error = at(path, n, table + " " + key) + " must be an integer in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]",
           false;
  *out = static_cast<Int>(*v);
  return true;
}

bool read_string(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                 std::string* out, std::string* error);
bool read_bool(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool* out,
               std::string* error);
// `joint = "name"` or `joint = 12` (a glTF node index); required.
bool read_joint(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                layers::JointRef* out, std::string* error);
// `key = [x, y, z]`, three finite numbers.
bool read_vec3(const std::string& path, const toml::table& t, const std::string& table, const char* key, double out[3],
               std::string* error);
// A number key's range, checked after reading: the message names the key
// and the range.
bool in_range(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool ok,
              const std::string& range, std::string* error);

// Every table of the array of tables `[[name]]` in `root` (the spec's top
// level, or the table `parent`: `[[parent.name]]`), in order.
template <typename Read>
bool each_table(const std::string& path, const toml::table& root, const char* name, Read&& read, std::string* error,
                const std::string& parent = "") {
  const toml::node* n = root.get(name);
  if (n == nullptr) return true;
  const std::string label = "[[" + (parent.empty() ? std::string() : parent + ".") + name + "]]";
  const toml::array* a = n->as_array();
  if (a == nullptr) return *error = at(path, n, label) + " must be an array of tables", false;
  for (const toml::node& e : *a) {
    const toml::table* tt = e.as_table();
    if (tt == nullptr) return *error = at(path, &e, label) + " must be a table", false;
    if (!read(*tt)) return false;
  }
  return true;
}

// The table `[name]` at the top of `root`, if present: *on = true, *where its position.
template <typename Read>
bool single_table(const std::string& path, const toml::table& root, const char* name, bool* on, std::string* where,
                  Read&& read, std::string* error) {
  const toml::node* n = root.get(name);
  if (n == nullptr) return true;
  const std::string label = std::string("[") + name + "]";
  const toml::table* tt = n->as_table();
  if (tt == nullptr) return *error = at(path, n, label) + " must be a table", false;
  *on = true;
  *where = at(path, n, label);
  return read(*tt);
}

}  // namespace sinew::rigc::spec_read
