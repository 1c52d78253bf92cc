#include "run/block_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace railcosim::run {

BlockWriter::BlockWriter(std::filesystem::path path, Limits limits,
                         std::function<Clock::time_point()> now)
    : path_(std::move(path)), limits_(limits), now_(std::move(now)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0)
    throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
}

BlockWriter::~BlockWriter() {
  try {
    close();
  } catch (const std::exception&) {
    // The failure was already reported by the call that met it, or the
    // owner is unwinding from another error that matters more.
  }
}

void BlockWriter::append(std::string_view text) {
  if (fd_ < 0) return;
  const auto t = now_();
  if (lines_held_ == 0) oldest_ = t;
  block_.append(text);
  lines_held_ += std::count(text.begin(), text.end(), '\n');
  if (lines_held_ >= limits_.rows || t - oldest_ >= limits_.age) write_block();
}

void BlockWriter::flush() {
  if (fd_ >= 0 && !block_.empty()) write_block();
}

void BlockWriter::close() {
  if (fd_ < 0) return;
  flush();
  if (::close(fd_) != 0) {
    fd_ = -1;
    throw std::runtime_error("cannot write " + path_.string() + ": " + std::strerror(errno));
  }
  fd_ = -1;
}

void BlockWriter::write_block() {
  std::size_t done = 0;
  while (done < block_.size()) {
    const ssize_t n = ::write(fd_, block_.data() + done, block_.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    const std::string why = n == 0 ? "nothing written" : std::strerror(errno);
    // Keep the whole lines that reached the file, drop a torn last one.
    const std::string_view sent(block_.data(), done);
    const std::size_t cut = sent.rfind('\n');
    const std::size_t keep = cut == std::string_view::npos ? 0 : cut + 1;
    if (::ftruncate(fd_, static_cast<off_t>(bytes_written_ + keep)) == 0) {
      lines_written_ += std::count(sent.begin(), sent.begin() + static_cast<long>(keep), '\n');
      bytes_written_ += keep;
    } else {
      lines_written_ += std::count(sent.begin(), sent.end(), '\n');
      bytes_written_ += done;
    }
    ::close(fd_);
    fd_ = -1;
    block_.clear();
    lines_held_ = 0;
    throw std::runtime_error("cannot write " + path_.string() + ": " + why);
  }
  bytes_written_ += done;
  lines_written_ += lines_held_;
  block_.clear();
  lines_held_ = 0;
}

}  // namespace railcosim::run
