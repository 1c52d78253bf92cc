// A scene as text: what a node receives and parses with the master's own
// parser (common/scene.cpp), so that both run the same scene. The text is
// the canonical form Scene::text holds; a scene is changed after parsing
// only through with_keys(), which edits the text and parses it again.
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "scene.hpp"

namespace railcosim {

// One key of a scene file and its new value: `key` is "table.key" as in the
// scene reference (docs/scene-keys.md), e.g. "simulation.end_time";
// kLeftOut removes the key (its default applies).
struct SceneEdit {
  std::string key;
  std::variant<double, std::int64_t, bool, std::string, std::monostate> value;
};
inline constexpr std::monostate kLeftOut{};

// TOML text with each edit made, written again in canonical form: a key
// "table.key" (or deeper) is set, the tables on its way made as needed, or
// removed with kLeftOut. Throws std::invalid_argument naming the key when a
// part of its path is not a table; the values are the parser's to judge.
std::string edit_scene_text(const std::string& text, const std::string& source,
                            const std::vector<SceneEdit>& edits);

// `scene` with the keys set (added when absent), parsed again: every check
// of a scene file applies, and a bad value throws SceneError naming the key.
Scene with_keys(const Scene& scene, const std::vector<SceneEdit>& edits);

// Throws std::logic_error when `scene` is not what its text gives: a field
// set in code after parsing, which a node would not see.
void check_scene_text(const Scene& scene);

}  // namespace railcosim
