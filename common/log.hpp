// One named logger per component ("master", "net", "vehicle", "track"),
// all writing to stderr.
#pragma once

#include <spdlog/spdlog.h>

#include <memory>
#include <string>

namespace railcosim {

std::shared_ptr<spdlog::logger> logger(const std::string& name);

}  // namespace railcosim
