#pragma once
// Builds small glTF 2.0 text files for tests (one base64 data-URI buffer), so
// each feature of the oracle (sparse, quantised, interleaved, CUBICSPLINE...)
// can be checked against values derived by hand.
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sinew::oracle::testing {

class GltfBuilder {
 public:
  GltfBuilder();

  // Appends `values` as a new bufferView (4-byte aligned); returns its index.
  template <typename T>
  int add_view(const std::vector<T>& values, int byte_stride = 0) {
    std::vector<unsigned char> raw(values.size() * sizeof(T));
    if (!raw.empty()) std::memcpy(raw.data(), values.data(), raw.size());
    return add_raw_view(raw, byte_stride);
  }
  int add_raw_view(const std::vector<unsigned char>& raw, int byte_stride = 0);

  // Appends an accessor; `extra` members (normalized, byteOffset, sparse...) are merged in.
  int add_accessor(int view, int component_type, size_t count, const std::string& type,
                   const nlohmann::json& extra = nlohmann::json::object());

  // Writes the document (with its buffer) under the test temp directory; returns the path.
  std::string write(const std::string& file_name) const;

  nlohmann::json doc;

 private:
  std::vector<unsigned char> bytes_;
};

// A file path under the test temp directory, unique to this process; removed at exit.
std::string temp_path(const std::string& file_name);

}  // namespace sinew::oracle::testing
