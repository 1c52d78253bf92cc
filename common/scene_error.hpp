// The error a user's mistake in a scene file raises.
#pragma once

#include <stdexcept>

namespace railcosim {

// A user's mistake in a scene file or a scene override: the message names
// the file and the key to fix.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace railcosim
