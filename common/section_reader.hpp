// Strict reading of one TOML table of a scene ([vehicle], [irregularity],
// [wheel_flat]): typed keys, each key remembered when read, so that any key
// left over is reported as unknown. Errors are SceneError naming the file and
// the key ("scenes/car.toml: key 'vehicle.body_mass': must be positive").
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include "scene_error.hpp"

namespace railcosim {

class SectionReader {
 public:
  SectionReader(const toml::table& table, std::string table_name, std::string source)
      : table_(table), name_(std::move(table_name)), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(source_ + ": key '" + name_ + "." + key + "': " + what);
  }

  bool has(const std::string& key) const { return table_.get(key) != nullptr; }

  double number(const std::string& key) { return number_or(key, std::nullopt); }
  double number_or(const std::string& key, std::optional<double> fallback) {
    const toml::node* n = find(key, !fallback.has_value());
    if (!n) return *fallback;
    if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())) {
      if (!std::isfinite(*v)) fail(key, "must be a finite number");
      return *v;
    }
    fail(key, "must be a number");
  }
  double positive(const std::string& key) { return check_positive(key, number(key)); }
  double positive_or(const std::string& key, double fallback) {
    return check_positive(key, number_or(key, fallback));
  }
  double non_negative(const std::string& key) {
    const double v = number(key);
    if (!(v >= 0.0)) fail(key, "must be zero or positive (got " + str(v) + ")");
    return v;
  }
  long integer_or(const std::string& key, std::optional<long> fallback) {
    const toml::node* n = find(key, !fallback.has_value());
    if (!n) return *fallback;
    if (!n->is_integer()) fail(key, "must be an integer");
    return static_cast<long>(*n->value<int64_t>());
  }
  std::string string(const std::string& key) {
    const toml::node* n = find(key, true);
    if (!n->is_string()) fail(key, "must be a string");
    return *n->value<std::string>();
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
  const toml::node* find(const std::string& key, bool required) {
    used_.insert(key);
    const toml::node* n = table_.get(key);
    if (!n && required) fail(key, "missing (required here)");
    return n;
  }
  double check_positive(const std::string& key, double v) const {
    if (!(v > 0.0)) fail(key, "must be positive (got " + str(v) + ")");
    return v;
  }

  const toml::table& table_;
  std::string name_;
  std::string source_;
  std::set<std::string> used_;
  std::string unknown_hint_ = "unknown key";
};

}  // namespace railcosim
