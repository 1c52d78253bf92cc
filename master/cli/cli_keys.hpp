// `master keys`: the reference of every scene key, printed from the scene
// key table (common/scene_keys.hpp) as text or as Markdown
// (docs/scene-keys.md is that Markdown).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace railcosim::cli {

struct KeysArgs {
  CLI::App* command = nullptr;
  bool markdown = false;
  bool check = false;  // master --check: print what it would print, nothing else
};

// The reference: one section per table, one line (text) or row (Markdown)
// per key: type, default, range, unit, meaning.
std::string scene_keys_text();
std::string scene_keys_markdown();

// Adds `keys` to the master's command line, filling `a`.
void add_keys_command(CLI::App& app, KeysArgs& a);
// Prints the reference to stdout; the exit status.
int do_keys(const KeysArgs& a);

}  // namespace railcosim::cli
