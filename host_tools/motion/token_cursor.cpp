#include "token_cursor.hpp"

namespace sinew::motion {

bool TokenCursor::at_end() {
  skip_space();
  return line_ >= lines_.size();
}

Token TokenCursor::next() {
  skip_space();
  const std::string_view text = lines_[line_].text;
  size_t end = column_;
  while (end < text.size() && !is_space(text[end])) ++end;
  const Token token{text.substr(column_, end - column_), lines_[line_].number, line_};
  column_ = end;
  return token;
}

bool TokenCursor::peek_on_line(size_t line, Token* token) {
  if (at_end()) return false;
  TokenCursor copy = *this;
  *token = copy.next();
  return token->line == line;
}

void TokenCursor::skip_space() {
  while (line_ < lines_.size()) {
    const std::string_view text = lines_[line_].text;
    while (column_ < text.size() && is_space(text[column_])) ++column_;
    if (column_ < text.size()) return;
    ++line_;
    column_ = 0;
  }
}

}  // namespace sinew::motion
