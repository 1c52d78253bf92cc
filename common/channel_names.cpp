#include "channel_names.hpp"

#include <map>

namespace railcosim {

std::string channel_name_fault(const std::string& name) {
  if (name.empty()) return "an empty name";
  if (name.size() > kMaxChannelNameLength)
    return "a name of " + std::to_string(name.size()) + " characters (at most " +
           std::to_string(kMaxChannelNameLength) + ")";
  auto letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
  if (!letter(name[0])) return "a name that does not start with a letter";
  for (char c : name)
    if (!letter(c) && !(c >= '0' && c <= '9') && c != '_')
      return "a name with a character other than A-Z, a-z, 0-9 and _";
  return "";
}

namespace {

// The name as it may be printed: only its acceptable characters, the others as '?'.
std::string printable(const std::string& name) {
  std::string s = name.substr(0, kMaxChannelNameLength);
  for (char& c : s)
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      c = '?';
  if (name.size() > s.size()) s += "...";
  return s;
}

}  // namespace

std::string check_declared_channels(const std::vector<std::pair<std::string, Channels>>& declared) {
  for (const char* kind : {"history channel", "result field"}) {
    const bool history = std::string(kind) == "history channel";
    std::map<std::string, std::string> owner;
    for (const auto& [who, channels] : declared)
      for (const std::string& name : history ? channels.history : channels.results) {
        if (const std::string why = channel_name_fault(name); !why.empty())
          return who + " declares the " + kind + " '" + printable(name) + "': " + why +
                 "; a name is 1 to 64 characters from A-Z, a-z, 0-9 and _, the first a letter";
        const auto [it, fresh] = owner.emplace(name, who);
        if (!fresh)
          return who + " declares the " + kind + " '" + name + "', which " +
                 (it->second == who ? std::string("it declares already")
                                    : it->second + " declares too");
      }
  }
  return "";
}

}  // namespace railcosim
