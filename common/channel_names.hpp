// The names participants declare for their outputs (history channels and
// result fields; docs/protocol.md §12). They become history.csv column names
// and summary keys as they are, so only plain names are accepted: 1 to 64
// characters from A-Z, a-z, 0-9 and _, the first a letter; and no name twice
// in a run, whichever participants declare them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "participant.hpp"

namespace railcosim {

inline constexpr std::size_t kMaxChannelNameLength = 64;

// Why `name` is not an acceptable channel name ("" if it is).
std::string channel_name_fault(const std::string& name);

// Checks every participant's declarations: each name acceptable, none
// declared twice (by one participant or by two). `declared` holds, per
// participant, a name for messages ("the soil node at HOST:PORT") and its
// channels. Returns what is wrong, naming the participant and the name, or "".
std::string check_declared_channels(const std::vector<std::pair<std::string, Channels>>& declared);

}  // namespace railcosim
