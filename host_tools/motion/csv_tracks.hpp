// Joint-angle tracks from CSV: one row per sample, linear interpolation between
// samples.
//
//   # comment lines and blank lines are ignored
//   time,elbow.flex,wrist.twist
//   0.0, 10, 0
//   0.5, 45, -5.5
//
// The first column is the time in seconds, strictly increasing; every other
// column is one degree of freedom named <joint>.<dof>, in degrees. Fields are
// separated by commas (no quoting) and may carry surrounding spaces.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sinew::motion {

struct TrackName {
  std::string joint;
  std::string dof;
};

struct JointTracks {
  std::vector<TrackName> tracks;  // one per column after "time"
  std::vector<double> times;      // seconds, strictly increasing, at least one
  std::vector<double> values;     // times.size() rows of tracks.size() values, sample-major

  // Index of the track named <joint>.<dof>, if present.
  std::optional<size_t> find(std::string_view joint, std::string_view dof) const;
};

// On failure returns false and sets `error` to "line <n>, column <c>: <problem>"
// (columns are 1-based field numbers) or "line <n>: <problem>".
bool parse_csv_tracks(std::string_view text, JointTracks* out, std::string* error);

// Reads and parses a file; errors are prefixed with the path.
bool load_csv_tracks(const std::string& path, JointTracks* out, std::string* error);

// Value of one track at `time`: linear between samples, held at the first and
// last sample outside their range (NaN counts as before the start).
// Throws std::out_of_range for a bad track index.
double sample_track(const JointTracks& tracks, size_t track, double time);

// Every track at `time`, in column order.
std::vector<double> sample_tracks(const JointTracks& tracks, double time);

}  // namespace sinew::motion
