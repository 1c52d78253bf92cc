// Strict reading of a scene file's tables (common/scene.cpp): every key
// through its entry of the scene key table (scene_keys.hpp), each remembered
// when read, so that anything left over is reported as unknown.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "scene_checks.hpp"
#include "scene_error.hpp"
#include "scene_keys.hpp"
#include "section_reader.hpp"

namespace railcosim {

// Reads typed keys from a TOML document, each through its entry of the
// scene key table (type, default, plain range), and remembers which it
// consumed, so that anything left over can be reported as an unknown key.
class SceneReader {
 public:
  SceneReader(const toml::table& root, std::string source)
      : root_(root), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(source_ + ": key '" + key + "': " + what);
  }

  // The key's node: nullptr when absent and optional.
  const toml::node* find(const std::string& table, const std::string& key) {
    const SceneKey& k = scene_key(table, key);
    used_[table].insert(key);
    const auto* tbl = root_.get(table) ? root_.get(table)->as_table() : nullptr;
    const toml::node* node = tbl ? tbl->get(key) : nullptr;
    if (!node && k.required) fail(table + "." + key, "missing (every scene must set it)");
    return node;
  }
  // Whether the file has the table (marked as read: its keys are looked up
  // one by one).
  bool present_table(const std::string& table) {
    used_[table];
    return root_.get(table) != nullptr;
  }
  // Whether the file sets an optional key (marked as read).
  bool present(const std::string& table, const std::string& key) {
    scene_key(table, key);
    used_[table].insert(key);
    const auto* tbl = root_.get(table) ? root_.get(table)->as_table() : nullptr;
    return tbl && tbl->get(key);
  }

  double number(const std::string& table, const std::string& key) {
    const SceneKey& k = scene_key(table, key);
    const toml::node* n = find(table, key);
    const double v = n ? key_number(*n, failer(table, key)) : default_number(k);
    return key_in_range(k, v, failer(table, key));
  }
  long integer(const std::string& table, const std::string& key) {
    const SceneKey& k = scene_key(table, key);
    const toml::node* n = find(table, key);
    if (!n) return static_cast<long>(default_number(k));
    const std::int64_t v = key_integer(*n, failer(table, key));
    if (auto why = integer_range_error(v); !why.empty()) fail(table + "." + key, why);
    key_in_range(k, static_cast<double>(v), failer(table, key));
    return static_cast<long>(v);
  }
  // A string or a choice (its entry's default when absent).
  std::string string(const std::string& table, const std::string& key) {
    const SceneKey& k = scene_key(table, key);
    const toml::node* n = find(table, key);
    return n ? key_string(k, *n, failer(table, key)) : k.default_text;
  }
  bool boolean(const std::string& table, const std::string& key) {
    const SceneKey& k = scene_key(table, key);
    const toml::node* n = find(table, key);
    return n ? key_boolean(*n, failer(table, key)) : default_number(k) != 0.0;
  }

  // A table read by its own parser (which looks its keys up and rejects
  // unknown keys itself), or handed whole to a participant (an entry "*");
  // nullptr if the file has none.
  const toml::table* whole_table(const std::string& table) {
    const toml::node* n = root_.get(table);
    if (!n) return nullptr;
    const toml::table* t = n->as_table();
    if (!t) fail(table, "must be a table ([" + table + "])");
    for (const auto& [k, v] : *t) {
      (void)v;
      used_[table].insert(std::string(k.str()));
    }
    used_[table];
    return t;
  }

  // Every table and key in the file must have been read.
  void reject_unknown() const {
    for (const auto& [tname, tnode] : root_) {
      const std::string table(tname.str());
      const auto it = used_.find(table);
      if (it == used_.end()) fail(table, "unknown table");
      const auto* tbl = tnode.as_table();
      if (!tbl) fail(table, "must be a table ([" + table + "])");
      for (const auto& [kname, knode] : *tbl) {
        (void)knode;
        if (!it->second.count(std::string(kname.str())))
          fail(table + "." + std::string(kname.str()), "unknown key");
      }
    }
  }

 private:
  KeyFail failer(const std::string& table, const std::string& key) const {
    return {source_, table + "." + key};
  }

  const toml::table& root_;
  std::string source_;
  std::map<std::string, std::set<std::string>> used_;
};

}  // namespace railcosim
