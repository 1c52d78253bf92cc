// Strict reading of the keys of a scene: every key through its entry of the
// scene key table (scene_keys.hpp) for its type, default and plain range.
// `key_value` and friends read one present key; SectionReader reads one
// table ([vehicle], [irregularity], [wheel_flat], an entry of
// [[vehicle.cars]]), each key remembered when read, so that any key left
// over is reported as unknown. Errors are SceneError naming the file and the
// key ("scenes/car.toml: key 'vehicle.body_mass': must be positive"; in the
// second entry of an array of tables, counted from 1: "key
// 'vehicle.cars[2].body_mass'").
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scene_error.hpp"
#include "scene_keys.hpp"

namespace railcosim {

// Throws the SceneError "<source>: key '<table.key>': <what>".
struct KeyFail {
  const std::string& source;
  std::string name;  // table.key
  [[noreturn]] void operator()(const std::string& what) const {
    throw SceneError(source + ": key '" + name + "': " + what);
  }
};

// The value of a present key as a number, integer, string or boolean, its
// type checked. The range is checked by key_in_range.
inline double key_number(const toml::node& n, const KeyFail& fail) {
  if (auto v = n.value<double>(); v && (n.is_floating_point() || n.is_integer())) {
    if (!std::isfinite(*v)) fail("must be a finite number");
    return *v;
  }
  fail("must be a number");
}
inline std::int64_t key_integer(const toml::node& n, const KeyFail& fail) {
  if (!n.is_integer()) fail("must be an integer");
  return *n.value<std::int64_t>();
}
inline std::string key_string(const SceneKey& k, const toml::node& n, const KeyFail& fail) {
  if (!n.is_string()) fail("must be a string");
  std::string v = *n.value<std::string>();
  if (k.type == KeyType::choice)
    if (std::string why = choice_error(k, v); !why.empty()) fail(why);
  return v;
}
inline bool key_boolean(const toml::node& n, const KeyFail& fail) {
  if (!n.is_boolean()) fail("must be true or false");
  return *n.value<bool>();
}
inline double key_in_range(const SceneKey& k, double v, const KeyFail& fail) {
  if (std::string why = k.range.error(v); !why.empty()) fail(why);
  return v;
}

class SectionReader {
 public:
  // `shown`: the table's name in errors, when not `table_name` (the name of
  // its entries in the key table), e.g. "vehicle.cars[2]".
  SectionReader(const toml::table& table, std::string table_name, std::string source,
                std::string shown = "")
      : table_(table),
        name_(std::move(table_name)),
        shown_(shown.empty() ? name_ : std::move(shown)),
        source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(source_ + ": key '" + shown_ + "." + key + "': " + what);
  }

  bool has(const std::string& key) const {
    scene_key(name_, key);
    return table_.get(key) != nullptr;
  }

  // An optional sub-table ([table.key]), read whole by its own reader;
  // nullptr when absent.
  const toml::table* subtable(const std::string& key) {
    const SceneKey& k = scene_key(name_, key);
    const toml::node* n = find(k);
    if (n == nullptr) return nullptr;
    const toml::table* t = n->as_table();
    if (t == nullptr) fail(key, "must be a table ([" + shown_ + "." + key + "])");
    return t;
  }

  // A number: required, or its entry's default when absent; in its range.
  double number(const std::string& key) {
    const SceneKey& k = scene_key(name_, key);
    const toml::node* n = find(k);
    const double v = n ? key_number(*n, failer(key)) : default_number(k);
    return key_in_range(k, v, failer(key));
  }
  // A number whose default the parser computes (the entry says which).
  double number_or(const std::string& key, double computed) {
    const SceneKey& k = scene_key(name_, key);
    if (k.required || !std::isnan(k.default_number))
      throw std::logic_error("scene key '" + name_ + "." + key + "' has no computed default");
    const toml::node* n = find(k);
    const double v = n ? key_number(*n, failer(key)) : computed;
    return key_in_range(k, v, failer(key));
  }
  long integer(const std::string& key) {
    const SceneKey& k = scene_key(name_, key);
    const toml::node* n = find(k);
    const double fallback = n ? 0.0 : default_number(k);
    const long v =
        n ? static_cast<long>(key_integer(*n, failer(key))) : static_cast<long>(fallback);
    key_in_range(k, static_cast<double>(v), failer(key));
    return v;
  }
  // A string or a choice (required, or its entry's default).
  std::string string(const std::string& key) {
    const SceneKey& k = scene_key(name_, key);
    const toml::node* n = find(k);
    return n ? key_string(k, *n, failer(key)) : k.default_text;
  }

  // A required array of tables ([[table.key]]): its entries, at most
  // `max_entries` of them and at least one, counted before any is read.
  const toml::array& tables(const std::string& key, std::size_t max_entries) {
    const SceneKey& k = scene_key(name_, key);
    const toml::node* n = find(k);
    const toml::array* a = n ? n->as_array() : nullptr;
    const std::string header = "[[" + name_ + "." + key + "]]";
    if (a && a->empty()) fail(key, "has no entries (give at least one " + header + ")");
    if (!a || !a->is_array_of_tables())
      fail(key, "must be an array of tables, each entry under a " + header + " header");
    if (a->size() > max_entries)
      fail(key, std::to_string(a->size()) + " entries, more than the " +
                    std::to_string(max_entries) + " allowed");
    return *a;
  }

  // Every key of the table must have been read.
  void reject_unknown() const {
    for (const auto& [k, v] : table_) {
      (void)v;
      if (!used_.count(std::string(k.str()))) fail(std::string(k.str()), unknown_hint_);
    }
  }
  // Appended to "unknown key" (e.g. "for model = \"car\"").
  void set_unknown_hint(std::string hint) { unknown_hint_ = "unknown key " + std::move(hint); }

  static std::string str(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

 private:
  KeyFail failer(const std::string& key) const { return {source_, shown_ + "." + key}; }
  const toml::node* find(const SceneKey& k) {
    used_.insert(k.key);
    const toml::node* n = table_.get(k.key);
    if (!n && k.required) fail(k.key, "missing (required here)");
    return n;
  }

  const toml::table& table_;
  std::string name_;
  std::string shown_;
  std::string source_;
  std::set<std::string> used_;
  std::string unknown_hint_ = "unknown key";
};

}  // namespace railcosim
