#include "toml_reader.hpp"

#include <cmath>

namespace sinew::rigc::spec_read {

std::string at(const std::string& path, const toml::node* n, const std::string& key) {
  std::string s = path;
  if (n != nullptr) s += ":" + std::to_string(n->source().begin.line);
  return s + ": " + key;
}

bool known_keys(const std::string& path, const toml::table& t, const std::string& table,
                std::initializer_list<const char*> keys, std::string* error) {
  for (const auto& [key, node] : t) {
    bool ok = false;
    for (const char* k : keys) ok |= key.str() == k;
    if (!ok) return *error = at(path, &node, table + " " + std::string(key.str())) + ": unknown key", false;
  }
  return true;
}

bool read_number(const std::string& path, const toml::table& t, const std::string& table, const char* key, double* out,
                 std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value<double>();
  if (!v || !std::isfinite(*v)) return *error = at(path, n, table + " " + key) + " must be a finite number", false;
  *out = *v;
  return true;
}

bool read_string(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                 std::string* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<std::string>();
  if (!v) return *error = at(path, n, table + " " + key) + " must be a string", false;
  *out = *v;
  return true;
}

bool read_bool(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool* out,
               std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<bool>();
  if (!v) return *error = at(path, n, table + " " + key) + " must be true or false", false;
  *out = *v;
  return true;
}

bool read_joint(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                layers::JointRef* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return *error = at(path, &t, table + " " + key) + " is required", false;
  out->where = at(path, n, table + " " + key);
  if (const auto name = n->value_exact<std::string>()) return out->name = *name, true;
  if (const auto node = n->value_exact<int64_t>(); node && *node >= 0 && *node < (int64_t{1} << 30))
    return out->node = static_cast<int>(*node), true;
  return *error = out->where + " must be a joint name or a glTF node index", false;
}

bool read_vec3(const std::string& path, const toml::table& t, const std::string& table, const char* key, double out[3],
               std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const toml::array* a = n->as_array();
  bool good = a != nullptr && a->size() == 3;
  for (size_t i = 0; good && i < 3; ++i) {
    const auto v = a->get(i)->value<double>();
    good = v && std::isfinite(*v);
    if (good) out[i] = *v;
  }
  if (!good) return *error = at(path, n, table + " " + key) + " must be an array of 3 numbers", false;
  return true;
}

bool in_range(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool ok,
              const std::string& range, std::string* error) {
  if (ok) return true;
  return *error = at(path, t.get(key), table + " " + key) + " must be " + range, false;
}

}  // namespace sinew::rigc::spec_read
