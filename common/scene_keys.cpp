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

std::string key_number_text(double v) {
  if (std::abs(v) < 1e8 && v == std::trunc(v)) return std::to_string(static_cast<long long>(v));
  std::string t = shortest(v);
  const std::size_t e = t.find('e');
  if (e == std::string::npos) return t;
  std::size_t digits = e + 1;
  std::string exponent = t[digits] == '-' ? "-" : "";
  if (t[digits] == '-' || t[digits] == '+') ++digits;
  while (digits + 1 < t.size() && t[digits] == '0') ++digits;
  return t.substr(0, e + 1) + exponent + t.substr(digits);
}

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
  const std::string a = key_number_text(lo), b = key_number_text(hi);
  std::ostringstream t;
  if (std::isinf(hi))
    t << (lo_open ? "> " : "≥ ") << a;
  else if (std::isinf(lo))
    t << (hi_open ? "< " : "≤ ") << b;
  else if (!lo_open && !hi_open)
    t << a << " … " << b;
  else
    t << (lo_open ? "(" : "[") << a << ", " << b << (hi_open ? ")" : "]");
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
