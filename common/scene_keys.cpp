#include "scene_keys.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace railcosim {
namespace {

thread_local SceneKeyTrace* g_trace = nullptr;
thread_local std::set<std::string>* g_trace_keys = nullptr;

std::string shortest(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

bool KeyRange::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string KeyRange::error(double v) const {
  if (unbounded() || contains(v)) return "";
  switch (got) {
    case Got::none:
      return message;
    case Got::shortest:
      return message + " (got " + shortest(v) + ")";
    case Got::fixed:
      return message + " (got " + std::to_string(v) + ")";
  }
  return message;
}

std::string KeyRange::text() const {
  if (unbounded()) return "";
  std::ostringstream t;
  if (std::isinf(hi))
    t << (lo_open ? "> " : "≥ ") << lo;
  else if (std::isinf(lo))
    t << (hi_open ? "< " : "≤ ") << hi;
  else if (!lo_open && !hi_open)
    t << lo << " … " << hi;
  else
    t << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  return t.str();
}

std::vector<std::string> scene_key_tables() {
  std::vector<std::string> tables;
  for (const SceneKey& k : scene_keys())
    if (std::find(tables.begin(), tables.end(), k.table) == tables.end()) tables.push_back(k.table);
  return tables;
}

const SceneKey& scene_key(std::string_view table, std::string_view key) {
  for (const SceneKey& k : scene_keys()) {
    if (k.table == table && k.key == key) {
      if (g_trace_keys) g_trace_keys->insert(k.table + "." + k.key);
      return k;
    }
  }
  throw std::logic_error("the scene key table (common/scene_key_table.cpp) has no entry for '" +
                         std::string(table) + "." + std::string(key) + "', which the parser reads");
}

std::string choice_error(const SceneKey& k, const std::string& value) {
  if (std::find(k.choices.begin(), k.choices.end(), value) != k.choices.end()) return "";
  std::string known;
  for (const std::string& c : k.choices) known += (known.empty() ? "" : ", ") + c;
  if (!k.noun.empty()) return "unknown " + k.noun + " '" + value + "' (known: " + known + ")";
  std::string alternatives;
  for (std::size_t i = 0; i < k.choices.size(); ++i) {
    if (i > 0) alternatives += i + 1 == k.choices.size() ? " or " : ", ";
    alternatives += "\"" + k.choices[i] + "\"";
  }
  return "must be " + alternatives + " (got \"" + value + "\")";
}

double default_number(const SceneKey& k) {
  if (k.required || std::isnan(k.default_number))
    throw std::logic_error("the scene key '" + k.table + "." + k.key +
                           "' has no default the parser can take as it is");
  return k.default_number;
}

SceneKeyTrace::SceneKeyTrace() : outer_(g_trace) {
  g_trace = this;
  g_trace_keys = &keys_;
}

SceneKeyTrace::~SceneKeyTrace() {
  g_trace = outer_;
  g_trace_keys = outer_ ? &outer_->keys_ : nullptr;
}

}  // namespace railcosim
