#include "libgpiod_chip.hpp"

#include <fcntl.h>
#include <gpiod.h>
#include <poll.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "line_queues.hpp"

namespace sinew::hal::gpio {

namespace {

// The v1 kernel FIFO holds 16 events per line; reading as many at once empties it in one call.
constexpr unsigned kReadBatch = 16;
constexpr size_t kStagedPerLine = 64;

std::string errno_text(const char* what, int err) { return std::string(what) + ": " + std::strerror(err); }

class LibgpiodGroup final : public LineGroup {
 public:
  LibgpiodGroup(std::vector<gpiod_line*> lines, std::vector<int> fds) : lines_(std::move(lines)), fds_(std::move(fds)) {
    queues_.init(lines_.size(), kStagedPerLine);
    for (int fd : fds_) pollfds_.push_back(pollfd{fd, POLLIN | POLLPRI, 0});
  }
  ~LibgpiodGroup() override {
    for (gpiod_line* l : lines_) gpiod_line_release(l);
  }

  int read_events(std::span<LineEvent> out) override {
    gpiod_line_event batch[kReadBatch];
    for (size_t i = 0; i < fds_.size(); ++i) {
      const uint32_t offset = gpiod_line_offset(lines_[i]);
      bool first = true;
      while (queues_.space(i) > 0) {
        const size_t want = queues_.space(i) < kReadBatch ? queues_.space(i) : kReadBatch;
        const int k = gpiod_line_event_read_fd_multiple(fds_[i], batch, static_cast<unsigned>(want));
        if (k < 0) {
          if (errno == EAGAIN || errno == EWOULDBLOCK) break;
          last_error_ = errno;
          return -1;
        }
        for (int e = 0; e < k; ++e) {
          const gpiod_line_event& ev = batch[e];
          const uint64_t ts =
              static_cast<uint64_t>(ev.ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ev.ts.tv_nsec);
          queues_.push(
              i, LineEvent{offset, ev.event_type == GPIOD_LINE_EVENT_RISING_EDGE ? Edge::kRising : Edge::kFalling, ts});
        }
        // A first read that fills a whole kernel FIFO may have been preceded by drops.
        if (first && static_cast<unsigned>(k) == kReadBatch) ++overflows_;
        first = false;
        if (static_cast<size_t>(k) < want) break;
      }
    }
    return static_cast<int>(queues_.pop_oldest(out));
  }

  WaitResult wait(uint64_t timeout_ns) override {
    if (!queues_.empty()) return WaitResult::kReady;
    for (pollfd& p : pollfds_) p.revents = 0;
    timespec ts{static_cast<time_t>(timeout_ns / 1'000'000'000u), static_cast<long>(timeout_ns % 1'000'000'000u)};
    const int r = ppoll(pollfds_.data(), pollfds_.size(), &ts, nullptr);
    if (r < 0) {
      if (errno == EINTR) return WaitResult::kTimeout;
      last_error_ = errno;
      return WaitResult::kError;
    }
    return r == 0 ? WaitResult::kTimeout : WaitResult::kReady;
  }

  bool get_levels(std::span<uint8_t> out) override {
    for (size_t i = 0; i < lines_.size() && i < out.size(); ++i) {
      const int v = gpiod_line_get_value(lines_[i]);
      if (v < 0) return last_error_ = errno, false;
      out[i] = static_cast<uint8_t>(v);
    }
    return true;
  }
  int last_error() const override { return last_error_; }
  uint64_t possible_overflows() const override { return overflows_; }

 private:
  uint64_t overflows_ = 0;
  std::vector<gpiod_line*> lines_;
  std::vector<int> fds_;
  std::vector<pollfd> pollfds_;
  LineQueues queues_;
  int last_error_ = 0;
};

class LibgpiodOutput final : public OutputLine {
 public:
  explicit LibgpiodOutput(gpiod_line* line) : line_(line) {}
  ~LibgpiodOutput() override { gpiod_line_release(line_); }
  bool set_level(bool high) override { return gpiod_line_set_value(line_, high ? 1 : 0) == 0; }

 private:
  gpiod_line* line_;
};

class LibgpiodChip final : public GpioChip {
 public:
  LibgpiodChip(gpiod_chip* chip, std::string consumer)
      : chip_(chip), name_(gpiod_chip_name(chip)), consumer_(std::move(consumer)) {}
  ~LibgpiodChip() override { gpiod_chip_close(chip_); }
  const char* name() const override { return name_.c_str(); }
  uint32_t line_count() const override { return gpiod_chip_num_lines(chip_); }

  std::unique_ptr<LineGroup> request_inputs(std::span<const uint32_t> offsets, std::string* error) override {
    std::vector<gpiod_line*> lines;
    std::vector<int> fds;
    auto release_all = [&] {
      for (gpiod_line* l : lines) gpiod_line_release(l);
    };
    for (uint32_t o : offsets) {
      gpiod_line* line = o < line_count() ? gpiod_chip_get_line(chip_, o) : nullptr;
      if (line == nullptr) {
        release_all();
        return *error = name_ + ": line " + std::to_string(o) + " does not exist", nullptr;
      }
      // One request per line: the v1 ABI gives every event line its own fd anyway.
      if (gpiod_line_request_both_edges_events(line, consumer_.c_str()) != 0) {
        const int err = errno;
        release_all();
        return *error = name_ + ": " + errno_text(("line " + std::to_string(o) + " events").c_str(), err), nullptr;
      }
      lines.push_back(line);
      const int fd = gpiod_line_event_get_fd(line);
      const int flags = fcntl(fd, F_GETFL);
      if (fd < 0 || flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0) {
        const int err = errno;
        release_all();
        return *error = name_ + ": " + errno_text(("line " + std::to_string(o) + " non-blocking").c_str(), err),
               nullptr;
      }
      fds.push_back(fd);
    }
    return std::make_unique<LibgpiodGroup>(std::move(lines), std::move(fds));
  }

  std::unique_ptr<OutputLine> request_output(uint32_t offset, bool initial_high, std::string* error) override {
    gpiod_line* line = offset < line_count() ? gpiod_chip_get_line(chip_, offset) : nullptr;
    if (line == nullptr) return *error = name_ + ": line " + std::to_string(offset) + " does not exist", nullptr;
    if (gpiod_line_request_output(line, consumer_.c_str(), initial_high ? 1 : 0) != 0)
      return *error = name_ + ": " + errno_text(("line " + std::to_string(offset) + " output").c_str(), errno), nullptr;
    return std::make_unique<LibgpiodOutput>(line);
  }

 private:
  gpiod_chip* chip_;
  std::string name_;
  std::string consumer_;
};

}  // namespace

std::unique_ptr<GpioChip> open_libgpiod_chip(const std::string& device, const std::string& consumer,
                                             std::string* error) {
  gpiod_chip* chip = gpiod_chip_open_lookup(device.c_str());
  if (chip == nullptr) return *error = errno_text(("gpio chip '" + device + "'").c_str(), errno), nullptr;
  return std::make_unique<LibgpiodChip>(chip, consumer);
}

}  // namespace sinew::hal::gpio
