#include "scene_text.hpp"

#include <toml++/toml.h>

#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace railcosim {

Scene with_keys(const Scene& scene, const std::vector<SceneEdit>& edits) {
  toml::table root = toml::parse(scene.text, scene.source);
  for (const SceneEdit& e : edits) {
    const auto dot = e.key.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == e.key.size())
      throw std::invalid_argument("scene edit '" + e.key + "': expected \"table.key\"");
    const std::string table = e.key.substr(0, dot), key = e.key.substr(dot + 1);
    toml::node* node = root.get(table);
    if (!node) node = &root.insert_or_assign(table, toml::table{}).first->second;
    toml::table* t = node->as_table();
    if (!t) throw std::invalid_argument("scene edit '" + e.key + "': " + table + " is not a table");
    std::visit(
        [&](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
            t->erase(key);
          else
            t->insert_or_assign(key, v);
        },
        e.value);
  }
  std::ostringstream text;
  text << root;
  return parse_scene(text.str(), scene.source, &scene.files);
}

void check_scene_text(const Scene& scene) {
  if (scene.text.empty())
    throw std::logic_error(scene.source + ": a scene without its text (built in code, not parsed)");
  if (!(parse_scene(scene.text, scene.source, &scene.files) == scene))
    throw std::logic_error(scene.source +
                           ": the scene was changed after it was read; change it with "
                           "with_keys() so that its text, which the nodes parse, says the same");
}

}  // namespace railcosim
