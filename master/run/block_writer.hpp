// Appends lines of text to a file in blocks: one write(2) per block instead
// of one per line. A block goes out when it holds `rows` lines or when its
// oldest line has waited `age` by the time another line comes, whichever is
// first; flush() and close() write what is held, and so does the destructor
// (a run that fails by an exception keeps every line it produced). A process
// killed outright loses at most the block it was holding.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace railcosim::run {

// When a block is written: at `rows` lines, or once its first line has
// waited `age`.
struct BlockLimits {
  long rows = 1024;
  std::chrono::milliseconds age{100};
};

class BlockWriter {
 public:
  using Clock = std::chrono::steady_clock;
  using Limits = BlockLimits;

  // Creates (truncates) `path`. Throws std::runtime_error naming the path
  // and the reason. `now` is the clock the age is measured by (tests pass
  // their own).
  explicit BlockWriter(std::filesystem::path path, Limits limits = {},
                       std::function<Clock::time_point()> now = Clock::now);
  ~BlockWriter();
  BlockWriter(const BlockWriter&) = delete;
  BlockWriter& operator=(const BlockWriter&) = delete;

  // Adds `text`, one or more whole lines (each ending in '\n'); writes the
  // block when it is due. Throws std::runtime_error naming the path and the
  // reason once a write fails; the file then ends at its last whole line and
  // later calls do nothing.
  void append(std::string_view text);
  // Writes what is held. Throws as append() does.
  void flush();
  // Flushes and closes the file. Throws as append() does.
  void close();

  // Whole lines in the file so far (those held are not counted).
  long lines_written() const { return lines_written_; }
  // Lines held, not yet written.
  long lines_held() const { return lines_held_; }
  // Bytes in the file so far.
  std::size_t bytes_written() const { return bytes_written_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  Limits limits_;
  std::function<Clock::time_point()> now_;
  int fd_ = -1;
  std::string block_;
  long lines_held_ = 0;
  Clock::time_point oldest_{};  // when the first held line came
  long lines_written_ = 0;
  std::size_t bytes_written_ = 0;
  // Writes the block; on failure cuts the file back to its last whole line,
  // closes it and throws.
  void write_block();
};

}  // namespace railcosim::run
