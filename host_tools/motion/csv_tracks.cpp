#include "csv_tracks.hpp"

#include <algorithm>
#include <stdexcept>

#include "parse_number.hpp"
#include "text_file.hpp"
#include "text_scan.hpp"

namespace sinew::motion {

namespace {

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

bool is_comment(std::string_view line) {
  const std::string_view body = trim(line);
  return !body.empty() && body.front() == '#';
}

class CsvTracksParser {
 public:
  CsvTracksParser(JointTracks* out, std::string* error) : out_(out), error_(error) {}

  bool parse(std::string_view text) {
    bool have_header = false;
    for (const TextLine& line : split_lines(text)) {
      if (is_blank(line.text) || is_comment(line.text)) continue;
      if (!have_header) {
        if (!parse_header(line)) return false;
        have_header = true;
      } else if (!parse_row(line)) {
        return false;
      }
    }
    if (!have_header) return fail_line(1, "no header: expected 'time,<joint>.<dof>,...'");
    if (out_->times.empty()) return fail_line(header_line_, "no samples after the header");
    return true;
  }

 private:
  bool fail_line(size_t line, const std::string& problem) {
    *error_ = cat("line ", std::to_string(line), ": ", problem);
    return false;
  }

  bool fail_field(size_t line, size_t column, const std::string& problem) {
    *error_ = cat("line ", std::to_string(line), ", column ", std::to_string(column), ": ", problem);
    return false;
  }

  std::string column_label(size_t column) const {
    if (column == 1) return "time";
    const TrackName& name = out_->tracks[column - 2];
    return cat(name.joint, ".", name.dof);
  }

  bool parse_header(const TextLine& line) {
    header_line_ = line.number;
    const std::vector<std::string_view> fields = split_commas(line.text);
    if (fields[0] != "time")
      return fail_field(line.number, 1, cat("the first column must be 'time', found ", quoted(fields[0])));
    if (fields.size() < 2) return fail_line(line.number, "the header names no joint tracks after 'time'");
    for (size_t i = 1; i < fields.size(); ++i) {
      const std::string_view field = fields[i];
      const size_t dot = field.rfind('.');
      const bool has_space = std::any_of(field.begin(), field.end(), is_space);
      if (dot == std::string_view::npos || dot == 0 || dot + 1 == field.size() || has_space)
        return fail_field(line.number, i + 1, cat(quoted(field), " is not a track name of the form <joint>.<dof>"));
      TrackName name{std::string(field.substr(0, dot)), std::string(field.substr(dot + 1))};
      if (out_->find(name.joint, name.dof))
        return fail_field(line.number, i + 1, cat("track ", quoted(field), " appears twice"));
      out_->tracks.push_back(std::move(name));
    }
    return true;
  }

  bool parse_row(const TextLine& line) {
    const std::vector<std::string_view> fields = split_commas(line.text);
    const size_t width = out_->tracks.size() + 1;
    if (fields.size() < width)
      return fail_field(line.number, fields.size() + 1,
                        cat("missing value for ", quoted(column_label(fields.size() + 1)), ": the row has ",
                            std::to_string(fields.size()), " fields, the header ", std::to_string(width)));
    if (fields.size() > width)
      return fail_field(line.number, width + 1,
                        cat("extra field: the row has ", std::to_string(fields.size()), " fields, the header ",
                            std::to_string(width)));
    std::vector<double> row(width);
    for (size_t i = 0; i < width; ++i) {
      std::string why;
      if (fields[i].empty())
        return fail_field(line.number, i + 1, cat("empty value for ", quoted(column_label(i + 1))));
      if (!parse_finite_double(fields[i], &row[i], &why))
        return fail_field(line.number, i + 1, cat(column_label(i + 1), ": ", why));
    }
    if (!out_->times.empty() && !(row[0] > out_->times.back()))
      return fail_field(
          line.number, 1,
          cat("time ", fields[0], " is not after the previous sample's (line ", std::to_string(previous_line_), ")"));
    out_->times.push_back(row[0]);
    out_->values.insert(out_->values.end(), row.begin() + 1, row.end());
    previous_line_ = line.number;
    return true;
  }

  JointTracks* out_;
  std::string* error_;
  size_t header_line_ = 0;
  size_t previous_line_ = 0;
};

}  // namespace

std::optional<size_t> JointTracks::find(std::string_view joint, std::string_view dof) const {
  for (size_t i = 0; i < tracks.size(); ++i)
    if (tracks[i].joint == joint && tracks[i].dof == dof) return i;
  return std::nullopt;
}

bool parse_csv_tracks(std::string_view text, JointTracks* out, std::string* error) {
  *out = JointTracks{};
  CsvTracksParser parser(out, error);
  if (parser.parse(text)) return true;
  *out = JointTracks{};
  return false;
}

bool load_csv_tracks(const std::string& path, JointTracks* out, std::string* error) {
  std::string text;
  if (!read_text_file(path, &text, error)) return false;
  if (parse_csv_tracks(text, out, error)) return true;
  *error = cat(path, ": ", *error);
  return false;
}

double sample_track(const JointTracks& tracks, size_t track, double time) {
  const size_t width = tracks.tracks.size();
  if (track >= width || tracks.times.empty() || tracks.values.size() != tracks.times.size() * width)
    throw std::out_of_range(cat("joint track ", std::to_string(track), " of ", std::to_string(width)));
  const auto value = [&](size_t sample) { return tracks.values[sample * width + track]; };
  const std::vector<double>& t = tracks.times;
  if (!(time > t.front())) return value(0);  // also NaN
  if (!(time < t.back())) return value(t.size() - 1);
  // First sample strictly after `time`; the one before it is at or before it.
  const auto after = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  const size_t before = after - 1;
  const double u = (time - t[before]) / (t[after] - t[before]);
  // This form cannot overflow for finite values and gives each sample exactly at u = 0 and 1.
  return (1 - u) * value(before) + u * value(after);
}

std::vector<double> sample_tracks(const JointTracks& tracks, double time) {
  std::vector<double> out(tracks.tracks.size());
  for (size_t k = 0; k < out.size(); ++k) out[k] = sample_track(tracks, k, time);
  return out;
}

}  // namespace sinew::motion
