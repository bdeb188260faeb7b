// Line and token helpers shared by the motion parsers. Motion files come from
// many tools and platforms, so a file may mix \n, \r\n and lone \r endings.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace sinew::motion {

struct TextLine {
  std::string_view text;  // without its line ending
  size_t number = 0;      // 1-based, as an editor shows it
};

// Splits on \n, \r\n and lone \r (mixed freely); drops a leading UTF-8 BOM.
// The views point into `text`, which must outlive them.
std::vector<TextLine> split_lines(std::string_view text);

bool is_space(char c);
std::string_view trim(std::string_view s);
bool is_blank(std::string_view s);
bool equals_ignore_case(std::string_view a, std::string_view b);

// Joins message pieces (strings, string views, literals) by appending. GCC 12
// at -O3 falsely reports -Wrestrict overlaps for "literal" + std::string
// temporaries, so messages are built this way instead.
template <typename... Pieces>
std::string cat(const Pieces&... pieces) {
  std::string out;
  (out.append(pieces), ...);
  return out;
}

// A token quoted for an error message: printable ASCII kept, other bytes as
// \xNN, long tokens shortened, so hostile input cannot flood a message.
std::string quoted(std::string_view token);

}  // namespace sinew::motion
