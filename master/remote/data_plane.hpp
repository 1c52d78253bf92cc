// How coupling data travels between participants in separate processes.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace railcosim::remote {

enum class DataPlane {
  kRelay,   // lock-step: every value goes node -> master -> node, one macro step per request
  kDirect,  // the nodes send each other their data; the master grants windows of steps
};

inline std::string to_string(DataPlane d) {
  return d == DataPlane::kRelay ? "relay" : "direct";
}

// The windows of the direct data plane.
struct DirectOptions {
  long window_steps = 0;            // macro steps per window (0: the whole run in one)
  std::uint32_t report_steps = 64;  // a node reports at least every this many steps
};

// Throws std::invalid_argument naming the accepted values.
inline DataPlane parse_data_plane(const std::string& s) {
  if (s == "relay") return DataPlane::kRelay;
  if (s == "direct") return DataPlane::kDirect;
  throw std::invalid_argument("--data-plane must be relay or direct, not '" + s + "'");
}

}  // namespace railcosim::remote
