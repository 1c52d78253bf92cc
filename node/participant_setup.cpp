#include "participant_setup.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "participant.hpp"

namespace railcosim {

struct OwnConfig::Table {
  toml::table root;
};

bool Interface::receives_force() const {
  return receives == std::vector<Quantity>{Quantity::kForce};
}

std::string Interface::describe() const {
  return cut + " (" + (upper ? "upper" : "lower") + " side, " + std::to_string(n()) + " points)";
}

OwnConfig::OwnConfig(std::string source, std::string table)
    : source_(std::move(source)),
      table_name_(std::move(table)),
      table_(std::make_shared<const Table>()) {}

namespace {

toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source << ": line " << e.source().begin.line << ", column " << e.source().begin.column
      << ": not valid TOML: " << e.description();
    throw BadRequestError(s.str());
  }
}

}  // namespace

OwnConfig OwnConfig::parse(const std::string& text, const std::string& source,
                           const std::string& table) {
  OwnConfig c(source, table);
  c.text_ = text;
  c.table_ = std::make_shared<const Table>(Table{parse_toml(text, source)});
  return c;
}

OwnConfig OwnConfig::table_of(const std::string& file_text, const std::string& path,
                              const std::string& table) {
  const toml::table root = parse_toml(file_text, path);
  const toml::table* own = root[table].as_table();
  if (!own)
    throw BadRequestError(path + ": no [" + table + "] table (the configuration of the " + table +
                          " participant; --table names another)");
  std::ostringstream text;
  text << *own;
  OwnConfig c(path, table);
  c.text_ = text.str();
  c.table_ = std::make_shared<const Table>(Table{*own});
  return c;
}

bool OwnConfig::empty() const {
  return table_->root.empty();
}

std::vector<std::string> OwnConfig::keys() const {
  std::vector<std::string> out;
  for (const auto& [key, value] : table_->root) out.emplace_back(key.str());
  return out;
}

bool OwnConfig::has(std::string_view key) const {
  return table_->root.contains(key);
}

std::string OwnConfig::where(std::string_view key) const {
  const std::string name =
      table_name_.empty() ? std::string(key) : table_name_ + "." + std::string(key);
  return source_ + ": key '" + name + "'";
}

namespace {

[[noreturn]] void refuse(const OwnConfig& c, std::string_view key, const std::string& why) {
  throw BadRequestError(c.where(key) + ": " + why);
}

}  // namespace

double OwnConfig::number(std::string_view key) const {
  const toml::node* n = table_->root.get(key);
  if (!n) refuse(*this, key, "missing");
  if (const auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer()))
    return *v;
  refuse(*this, key, "expected a number");
}

double OwnConfig::number(std::string_view key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

long OwnConfig::integer(std::string_view key) const {
  const toml::node* n = table_->root.get(key);
  if (!n) refuse(*this, key, "missing");
  if (const auto v = n->value<std::int64_t>(); v && n->is_integer()) return static_cast<long>(*v);
  refuse(*this, key, "expected an integer");
}

bool OwnConfig::boolean(std::string_view key) const {
  const toml::node* n = table_->root.get(key);
  if (!n) refuse(*this, key, "missing");
  if (const auto v = n->value<bool>(); v && n->is_boolean()) return *v;
  refuse(*this, key, "expected true or false");
}

std::string OwnConfig::string(std::string_view key) const {
  const toml::node* n = table_->root.get(key);
  if (!n) refuse(*this, key, "missing");
  if (const auto v = n->value<std::string>(); v && n->is_string()) return *v;
  refuse(*this, key, "expected a string");
}

std::vector<double> OwnConfig::numbers(std::string_view key) const {
  const toml::node* n = table_->root.get(key);
  if (!n) refuse(*this, key, "missing");
  const toml::array* a = n->as_array();
  if (!a) refuse(*this, key, "expected an array of numbers");
  std::vector<double> out;
  for (const toml::node& e : *a) {
    const auto v = e.value<double>();
    if (!v || !(e.is_floating_point() || e.is_integer()))
      refuse(*this, key,
             "expected an array of numbers (entry " + std::to_string(out.size()) + " is not one)");
    out.push_back(*v);
  }
  return out;
}

}  // namespace railcosim
