#include "log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

#include <mutex>

namespace railcosim {

std::shared_ptr<spdlog::logger> logger(const std::string& name) {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  if (auto existing = spdlog::get(name)) return existing;
  auto l = spdlog::stderr_color_mt(name);
  l->set_pattern("[%H:%M:%S.%e] [%n] [%^%l%$] %v");
  return l;
}

}  // namespace railcosim
