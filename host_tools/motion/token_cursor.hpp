// Whitespace-separated tokens over numbered lines, for the BVH hierarchy.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "host_tools/motion/text_scan.hpp"

namespace sinew::motion {

struct Token {
  std::string_view text;
  size_t line = 0;        // 1-based line number
  size_t line_index = 0;  // index into the split lines
};

// The BVH hierarchy is free-form across lines, so it is read token by token;
// callers compare line numbers where one line must hold a whole statement
// (OFFSET, CHANNELS) and switch to whole lines for the frame rows.
class TokenCursor {
 public:
  explicit TokenCursor(const std::vector<TextLine>& lines) : lines_(lines) {}

  bool at_end();

  // The next token. Precondition: !at_end().
  Token next();

  // Without consuming anything: whether a next token exists and sits on
  // `line` (it is stored in `token` whenever one exists).
  bool peek_on_line(size_t line, Token* token);

  // For messages about input that stops too early.
  size_t last_line_number() const { return lines_.empty() ? 1 : lines_.back().number; }

 private:
  void skip_space();

  const std::vector<TextLine>& lines_;
  size_t line_ = 0;
  size_t column_ = 0;
};

}  // namespace sinew::motion
