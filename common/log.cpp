#include "log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <unistd.h>

#include <mutex>
#include <string>

namespace railcosim {

std::shared_ptr<spdlog::logger> logger(const std::string& name) {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  if (auto existing = spdlog::get(name)) return existing;
  auto l = spdlog::stderr_color_mt(name);
  // On a terminal a line starts by clearing the one it is written on, which
  // may hold a progress line (master/run/progress.hpp) redrawn in place.
  l->set_pattern(std::string(::isatty(STDERR_FILENO) != 0 ? "\r\033[K" : "") +
                 "[%H:%M:%S.%e] [%n] [%^%l%$] %v");
  return l;
}

}  // namespace railcosim
