// How the scene key table (scene_key_table.cpp) writes its entries: the
// ranges, and an entry under construction with its defaults, conditions and
// notes. Only the table includes it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "scene_checks.hpp"
#include "scene_keys.hpp"

namespace railcosim::key_table {

inline std::string number_text(double v) {
  return key_number_text(v);
}

inline KeyRange positive() {
  return {0.0, KeyRange{}.hi, true, false, "must be positive", KeyRange::Got::shortest};
}
inline KeyRange non_negative() {
  return {0.0, KeyRange{}.hi, false, false, "must be zero or positive", KeyRange::Got::shortest};
}
inline KeyRange closed(double lo, double hi, std::string message) {
  return {lo, hi, false, false, std::move(message), KeyRange::Got::none};
}

// One entry under construction: required unless given a default.
struct Entry {
  SceneKey k;
  Entry& range(KeyRange r) {
    k.range = std::move(r);
    return *this;
  }
  Entry& fallback(double v) {
    k.required = false;
    k.default_number = v;
    return *this;
  }
  // A default the parser computes, or what leaving the key out means.
  Entry& fallback_text(std::string text) {
    k.required = false;
    k.default_text = std::move(text);
    return *this;
  }
  Entry& note(std::string text) {
    k.range_note = std::move(text);
    return *this;
  }
  Entry& when(std::string condition) {
    k.when = std::move(condition);
    return *this;
  }
  Entry& words(std::vector<std::string> w) {
    k.choices = std::move(w);
    return *this;
  }
};

inline Entry key(std::string table, std::string name, KeyType type, std::string unit,
                 std::string meaning) {
  Entry e;
  e.k.table = std::move(table);
  e.k.key = std::move(name);
  e.k.type = type;
  e.k.required = true;
  e.k.unit = std::move(unit);
  e.k.meaning = std::move(meaning);
  return e;
}
inline Entry number(std::string table, std::string name, std::string unit, std::string meaning) {
  return key(std::move(table), std::move(name), KeyType::number, std::move(unit),
             std::move(meaning));
}
inline Entry integer(std::string table, std::string name, std::string meaning) {
  return key(std::move(table), std::move(name), KeyType::integer, "", std::move(meaning));
}
// A choice with its default (its first value unless `fallback` is given).
inline Entry choice(std::string table, std::string name, std::vector<std::string> values,
                    std::string noun, std::string meaning) {
  Entry e = key(std::move(table), std::move(name), KeyType::choice, "", std::move(meaning))
                .fallback_text(values.front());
  e.k.choices = std::move(values);
  e.k.noun = std::move(noun);
  return e;
}

// The resilient layers' entries (scene_key_table_layers.cpp), after [ballast].
void layer_keys(std::vector<Entry>& v);

}  // namespace railcosim::key_table
