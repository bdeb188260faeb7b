#include "bvh.hpp"

#include <array>
#include <stdexcept>

#include "parse_number.hpp"
#include "text_file.hpp"
#include "text_scan.hpp"
#include "token_cursor.hpp"

namespace sinew::motion {

namespace {

constexpr std::array<BvhChannel, 6> kAllChannels = {BvhChannel::kXposition, BvhChannel::kYposition,
                                                    BvhChannel::kZposition, BvhChannel::kXrotation,
                                                    BvhChannel::kYrotation, BvhChannel::kZrotation};
constexpr size_t kMaxChannelsPerJoint = 6;

bool channel_from_name(std::string_view name, BvhChannel* out) {
  for (const BvhChannel c : kAllChannels) {
    if (equals_ignore_case(name, channel_name(c))) {
      *out = c;
      return true;
    }
  }
  return false;
}

// One joint or End Site whose '{' has been read and whose '}' has not.
struct OpenBlock {
  bool end_site = false;
  size_t index = 0;  // into Bvh::joints or Bvh::end_sites
  size_t line = 0;   // line of its ROOT / JOINT / End keyword
  bool has_offset = false;
  bool has_channels = false;
};

class BvhParser {
 public:
  BvhParser(const std::vector<TextLine>& lines, Bvh* out, std::string* error)
      : lines_(lines), tokens_(lines), out_(out), error_(error) {}

  bool parse() { return parse_hierarchy() && parse_motion_header() && parse_rows(); }

 private:
  bool fail(size_t line, const std::string& problem) {
    *error_ = cat("line ", std::to_string(line), ": ", problem);
    return false;
  }

  bool fail_at_end(const std::string& problem) {
    return fail(tokens_.last_line_number(), cat("unexpected end of file (truncated?): ", problem));
  }

  std::string describe(const OpenBlock& block) const {
    const std::string where = cat(" (line ", std::to_string(block.line), ")");
    if (block.end_site) return cat("End Site", where);
    return cat("joint ", quoted(out_->joints[block.index].name), where);
  }

  bool parse_hierarchy() {
    if (tokens_.at_end()) return fail(1, "empty file: expected HIERARCHY");
    const Token first = tokens_.next();
    if (!equals_ignore_case(first.text, "HIERARCHY"))
      return fail(first.line, cat("expected HIERARCHY, found ", quoted(first.text)));
    while (true) {
      if (tokens_.at_end()) return fail_at_end(out_->joints.empty() ? "expected ROOT" : "expected MOTION");
      const Token token = tokens_.next();
      if (equals_ignore_case(token.text, "MOTION")) {
        if (out_->joints.empty()) return fail(token.line, "the HIERARCHY has no ROOT joint");
        return true;
      }
      if (!equals_ignore_case(token.text, "ROOT"))
        return fail(token.line, cat("expected ROOT or MOTION, found ", quoted(token.text)));
      if (!parse_joint_tree(token)) return false;
    }
  }

  // Reads one ROOT and everything below it. Iterative, so deeply nested input
  // cannot exhaust the call stack.
  bool parse_joint_tree(const Token& root_keyword) {
    std::vector<OpenBlock> open;
    if (!open_joint(root_keyword, -1, &open)) return false;
    while (!open.empty()) {
      if (tokens_.at_end()) return fail_at_end(cat("missing '}' for ", describe(open.back())));
      const Token token = tokens_.next();
      OpenBlock& block = open.back();
      if (equals_ignore_case(token.text, "OFFSET")) {
        if (!read_offset(token, &block)) return false;
      } else if (equals_ignore_case(token.text, "CHANNELS")) {
        if (!read_channels(token, &block)) return false;
      } else if (equals_ignore_case(token.text, "JOINT")) {
        if (block.end_site) return fail(token.line, "an End Site cannot contain a JOINT");
        if (!open_joint(token, static_cast<int>(block.index), &open)) return false;
      } else if (equals_ignore_case(token.text, "End")) {
        if (block.end_site) return fail(token.line, "an End Site cannot contain an End Site");
        if (!open_end_site(token, static_cast<int>(block.index), &open)) return false;
      } else if (token.text == "}") {
        if (!block.has_offset) return fail(token.line, cat(describe(block), " has no OFFSET"));
        open.pop_back();
      } else if (equals_ignore_case(token.text, "ROOT") || equals_ignore_case(token.text, "MOTION")) {
        return fail(token.line, cat(quoted(token.text), " before the closing '}' of ", describe(block)));
      } else {
        return fail(token.line, cat("unexpected ", quoted(token.text), " in ", describe(block),
                                    " (expected OFFSET, CHANNELS, JOINT, End Site or '}')"));
      }
    }
    return true;
  }

  // The name is the rest of the keyword's line (names may contain spaces), up
  // to an optional '{'; otherwise the '{' must come next.
  bool open_joint(const Token& keyword, int parent, std::vector<OpenBlock>* open) {
    std::string name;
    bool brace = false;
    Token token;
    while (!brace && tokens_.peek_on_line(keyword.line, &token)) {
      tokens_.next();
      std::string_view part = token.text;
      if (part.back() == '{') {
        part.remove_suffix(1);
        brace = true;
      }
      if (part.empty()) continue;
      if (!name.empty()) name += ' ';
      name.append(part);
    }
    if (name.empty()) return fail(keyword.line, cat(keyword.text, " without a name"));
    if (!brace && !expect_open_brace(cat(keyword.text, " ", quoted(name)))) return false;
    out_->joints.push_back({name, parent, {0, 0, 0}, {}, 0});
    open->push_back({false, out_->joints.size() - 1, keyword.line, false, false});
    return true;
  }

  bool open_end_site(const Token& keyword, int parent, std::vector<OpenBlock>* open) {
    if (tokens_.at_end()) return fail_at_end("expected 'Site' after 'End'");
    const Token site = tokens_.next();
    if (!equals_ignore_case(site.text, "Site") && !equals_ignore_case(site.text, "Site{"))
      return fail(site.line, cat("expected 'End Site', found 'End' ", quoted(site.text)));
    if (site.text.back() != '{' && !expect_open_brace("End Site")) return false;
    out_->end_sites.push_back({parent, {0, 0, 0}});
    open->push_back({true, out_->end_sites.size() - 1, keyword.line, false, false});
    return true;
  }

  bool expect_open_brace(const std::string& after) {
    if (tokens_.at_end()) return fail_at_end(cat("expected '{' after ", after));
    const Token token = tokens_.next();
    if (token.text != "{") return fail(token.line, cat("expected '{' after ", after, ", found ", quoted(token.text)));
    return true;
  }

  bool read_offset(const Token& keyword, OpenBlock* block) {
    if (block->has_offset) return fail(keyword.line, cat("second OFFSET in ", describe(*block)));
    Vec3 offset{};
    for (size_t axis = 0; axis < 3; ++axis) {
      Token token;
      if (!tokens_.peek_on_line(keyword.line, &token))
        return fail(keyword.line, cat("OFFSET needs 3 numbers, found ", std::to_string(axis)));
      tokens_.next();
      std::string why;
      if (!parse_finite_double(token.text, &offset[axis], &why)) return fail(token.line, cat("OFFSET: ", why));
    }
    Token extra;
    double ignored = 0;
    std::string why;
    if (tokens_.peek_on_line(keyword.line, &extra) && parse_finite_double(extra.text, &ignored, &why))
      return fail(keyword.line, "OFFSET has more than 3 numbers");
    if (block->end_site) {
      out_->end_sites[block->index].offset = offset;
    } else {
      out_->joints[block->index].offset = offset;
    }
    block->has_offset = true;
    return true;
  }

  bool read_channels(const Token& keyword, OpenBlock* block) {
    if (block->end_site) return fail(keyword.line, "an End Site cannot have CHANNELS");
    if (block->has_channels) return fail(keyword.line, cat("second CHANNELS in ", describe(*block)));
    Token token;
    if (!tokens_.peek_on_line(keyword.line, &token)) return fail(keyword.line, "CHANNELS without a count");
    tokens_.next();
    size_t count = 0;
    std::string why;
    if (!parse_count(token.text, &count, &why)) return fail(token.line, cat("CHANNELS count: ", why));
    if (count > kMaxChannelsPerJoint)
      return fail(token.line, cat("CHANNELS count ", std::to_string(count), ": a joint has at most 6 channels"));
    BvhJoint& joint = out_->joints[block->index];
    for (size_t i = 0; i < count; ++i) {
      if (!tokens_.peek_on_line(keyword.line, &token))
        return fail(keyword.line,
                    cat("CHANNELS declares ", std::to_string(count), " channels but lists ", std::to_string(i)));
      tokens_.next();
      BvhChannel channel{};
      if (!channel_from_name(token.text, &channel))
        return fail(token.line, cat("unknown channel ", quoted(token.text),
                                    " (expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)"));
      for (const BvhChannel seen : joint.channels)
        if (seen == channel)
          return fail(token.line, cat("channel ", channel_name(channel), " listed twice for ", describe(*block)));
      joint.channels.push_back(channel);
    }
    BvhChannel extra{};
    if (tokens_.peek_on_line(keyword.line, &token) && channel_from_name(token.text, &extra))
      return fail(keyword.line, cat("CHANNELS declares ", std::to_string(count), " channels but lists more"));
    joint.first_value = out_->channel_count;
    out_->channel_count += count;
    block->has_channels = true;
    return true;
  }

  // "Frames: 344" and "Frame Time: 0.0083333"; the value may be glued to its label.
  bool read_labelled_value(std::string_view label, std::string_view context, Token* value) {
    if (tokens_.at_end()) return fail_at_end(cat("expected '", context, "'"));
    const Token token = tokens_.next();
    if (!equals_ignore_case(token.text.substr(0, label.size()), label))
      return fail(token.line, cat("expected '", context, "', found ", quoted(token.text)));
    if (token.text.size() > label.size()) {
      *value = {token.text.substr(label.size()), token.line, token.line_index};
      return true;
    }
    if (!tokens_.peek_on_line(token.line, value)) return fail(token.line, cat("'", context, "' without a value"));
    tokens_.next();
    return true;
  }

  bool parse_motion_header() {
    Token frames;
    if (!read_labelled_value("Frames:", "Frames:", &frames)) return false;
    std::string why;
    if (!parse_count(frames.text, &out_->frame_count, &why)) return fail(frames.line, cat("Frames: ", why));
    frames_line_ = frames.line;

    if (tokens_.at_end()) return fail_at_end("expected 'Frame Time:'");
    const Token frame_word = tokens_.next();
    if (!equals_ignore_case(frame_word.text, "Frame"))
      return fail(frame_word.line, cat("expected 'Frame Time:', found ", quoted(frame_word.text)));
    Token time;
    if (!read_labelled_value("Time:", "Frame Time:", &time)) return false;
    if (!parse_finite_double(time.text, &out_->frame_time, &why)) return fail(time.line, cat("Frame Time: ", why));
    if (out_->frame_time <= 0) return fail(time.line, "Frame Time must be positive");
    Token extra;
    if (tokens_.peek_on_line(time.line, &extra))
      return fail(time.line, cat("unexpected ", quoted(extra.text), " after the Frame Time"));
    first_row_index_ = time.line_index + 1;
    return true;
  }

  std::string describe_value(size_t value_index) const {
    for (const BvhJoint& joint : out_->joints) {
      if (value_index >= joint.first_value && value_index < joint.first_value + joint.channels.size()) {
        return cat("joint ", quoted(joint.name), " ", channel_name(joint.channels[value_index - joint.first_value]));
      }
    }
    return "unassigned";
  }

  bool parse_rows() {
    const size_t width = out_->channel_count;
    out_->values.clear();
    // Reserve only what the remaining text could possibly hold (each value
    // takes at least two bytes), so a huge declared count cannot exhaust memory.
    size_t remaining_bytes = 0;
    for (size_t i = first_row_index_; i < lines_.size(); ++i) remaining_bytes += lines_[i].text.size() + 1;
    if (width > 0 && out_->frame_count <= remaining_bytes / (2 * width))
      out_->values.reserve(out_->frame_count * width);

    std::vector<std::string_view> fields;
    size_t rows = 0;
    for (size_t i = first_row_index_; i < lines_.size(); ++i) {
      const TextLine& line = lines_[i];
      if (is_blank(line.text)) continue;
      if (width == 0) return fail(line.number, "frame values found, but the hierarchy declares no channels");
      if (rows == out_->frame_count)
        return fail(line.number, cat("more frame rows than 'Frames: ", std::to_string(out_->frame_count),
                                     "' declares (line ", std::to_string(frames_line_), ")"));
      split_fields(line.text, &fields);
      if (fields.size() != width)
        return fail(line.number, cat("frame ", std::to_string(rows + 1), " has ", std::to_string(fields.size()),
                                     fields.size() == 1 ? " value" : " values", ", expected ", std::to_string(width),
                                     " (one per channel)"));
      for (size_t k = 0; k < width; ++k) {
        double value = 0;
        std::string why;
        if (!parse_finite_double(fields[k], &value, &why))
          return fail(line.number, cat("frame ", std::to_string(rows + 1), ", value ", std::to_string(k + 1), " (",
                                       describe_value(k), "): ", why));
        out_->values.push_back(value);
      }
      ++rows;
    }
    if (rows < out_->frame_count && width > 0)
      return fail_at_end(cat("file ends after ", std::to_string(rows), " of the ", std::to_string(out_->frame_count),
                             " frames declared at line ", std::to_string(frames_line_)));
    return true;
  }

  static void split_fields(std::string_view text, std::vector<std::string_view>* fields) {
    fields->clear();
    size_t i = 0;
    while (i < text.size()) {
      while (i < text.size() && is_space(text[i])) ++i;
      const size_t start = i;
      while (i < text.size() && !is_space(text[i])) ++i;
      if (i > start) fields->push_back(text.substr(start, i - start));
    }
  }

  const std::vector<TextLine>& lines_;
  TokenCursor tokens_;
  Bvh* out_;
  std::string* error_;
  size_t frames_line_ = 0;
  size_t first_row_index_ = 0;
};

}  // namespace

std::string_view channel_name(BvhChannel channel) {
  switch (channel) {
    case BvhChannel::kXposition:
      return "Xposition";
    case BvhChannel::kYposition:
      return "Yposition";
    case BvhChannel::kZposition:
      return "Zposition";
    case BvhChannel::kXrotation:
      return "Xrotation";
    case BvhChannel::kYrotation:
      return "Yrotation";
    case BvhChannel::kZrotation:
      return "Zrotation";
  }
  return "?";
}

bool is_rotation(BvhChannel channel) {
  return channel == BvhChannel::kXrotation || channel == BvhChannel::kYrotation || channel == BvhChannel::kZrotation;
}

int channel_axis(BvhChannel channel) {
  switch (channel) {
    case BvhChannel::kXposition:
    case BvhChannel::kXrotation:
      return 0;
    case BvhChannel::kYposition:
    case BvhChannel::kYrotation:
      return 1;
    case BvhChannel::kZposition:
    case BvhChannel::kZrotation:
      return 2;
  }
  return 0;
}

std::span<const double> Bvh::frame(size_t index) const {
  if (index >= frame_count || (index + 1) * channel_count > values.size())
    throw std::out_of_range(cat("BVH frame ", std::to_string(index), " of ", std::to_string(frame_count)));
  return std::span<const double>(values).subspan(index * channel_count, channel_count);
}

int Bvh::find_joint(std::string_view name) const {
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return -1;
}

bool parse_bvh(std::string_view text, Bvh* out, std::string* error) {
  *out = Bvh{};
  const std::vector<TextLine> lines = split_lines(text);
  BvhParser parser(lines, out, error);
  if (parser.parse()) return true;
  *out = Bvh{};
  return false;
}

bool load_bvh(const std::string& path, Bvh* out, std::string* error) {
  std::string text;
  if (!read_text_file(path, &text, error)) return false;
  if (parse_bvh(text, out, error)) return true;
  *error = cat(path, ": ", *error);
  return false;
}

}  // namespace sinew::motion
