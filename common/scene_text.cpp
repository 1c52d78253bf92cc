#include "scene_text.hpp"

#include <toml++/toml.h>

#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "toml_nesting.hpp"

namespace railcosim {

std::string edit_scene_text(const std::string& text, const std::string& source,
                            const std::vector<SceneEdit>& edits) {
  check_toml_nesting(text, source);
  toml::table root = toml::parse(text, source);
  for (const SceneEdit& e : edits) {
    std::vector<std::string> path;
    std::stringstream parts(e.key);
    for (std::string p; std::getline(parts, p, '.');) path.push_back(p);
    if (path.size() < 2)
      throw std::invalid_argument("scene key '" + e.key + "': expected \"table.key\"");
    toml::table* t = &root;
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      if (!t->contains(path[k])) t->insert(path[k], toml::table{});
      t = (*t)[path[k]].as_table();
      if (!t)
        throw std::invalid_argument("scene key '" + e.key + "': " + path[k] + " is not a table");
    }
    std::visit(
        [&](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
            t->erase(path.back());
          else
            t->insert_or_assign(path.back(), v);
        },
        e.value);
  }
  std::ostringstream out;
  out << root;
  return out.str();
}

Scene with_keys(const Scene& scene, const std::vector<SceneEdit>& edits) {
  return parse_scene(edit_scene_text(scene.text, scene.source, edits), scene.source, &scene.files);
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
