// The keys of a scene file as data: one entry per key the product reads
// (its table, type, default, range, unit and meaning). The parsers look every
// key up here (common/scene.cpp, common/excitation_toml.cpp), so the types,
// defaults and plain ranges they apply are the ones this table states, and
// `master keys` prints the reference (docs/scene-keys.md) from it.
#pragma once

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace railcosim {

enum class KeyType {
  number,   // a finite number (integers accepted)
  integer,  // a whole number (and, if `choices` is not empty, one of those words)
  string,
  boolean,
  choice,  // a string among `choices`
  table,   // the rest of the table, handed whole to a participant
  tables,  // an array of tables: entries [[table.key]], whose keys are the table "table.key"
};

// A plain range: the value lies between lo and hi (each end open or closed).
// `message` is the error when it does not; `got` says how the value is
// appended to it ("(got 7)").
struct KeyRange {
  enum class Got { none, shortest, fixed };
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  std::string message;
  Got got = Got::none;

  bool unbounded() const { return std::isinf(lo) && std::isinf(hi); }
  bool contains(double v) const;
  // The error for `v` ("" when it lies inside).
  std::string error(double v) const;
  // "> 0", "≥ 0", "(0, 10]", "1 … 6" ("" when unbounded).
  std::string text() const;
};

struct SceneKey {
  std::string table;
  std::string key;  // "*": any other key of the table (type table)
  KeyType type = KeyType::number;
  // choice: the values; integer: the words it accepts besides a number.
  std::vector<std::string> choices;
  // choice: what a value names, for the error "unknown soil model 'x' (known:
  // ...)"; empty: "must be \"a\" or \"b\" (got \"x\")".
  std::string noun;
  bool required = false;  // when it applies (see `when`)
  // A default the parser takes as it is: a number (integer and boolean: 0 or
  // 1 for false and true), or for strings and choices `default_text`. NaN with
  // `default_text` set: a default the parser computes, or what leaving the key
  // out means, as prose.
  double default_number = std::numeric_limits<double>::quiet_NaN();
  std::string default_text;
  KeyRange range;          // checked by the parser as it reads the key
  std::string range_note;  // the checks beyond the plain range, as prose
  std::string unit;
  std::string when;  // the condition under which the key applies ("": always)
  std::string meaning;
};

// Every entry, in the order of the reference.
const std::vector<SceneKey>& scene_keys();
// The tables in the order of the reference.
std::vector<std::string> scene_key_tables();

// The entry of `table.key`. A key the parser reads without an entry is a
// programming error: throws std::logic_error naming it.
const SceneKey& scene_key(std::string_view table, std::string_view key);

// The error for a choice's value ("" when it is one of the choices).
std::string choice_error(const SceneKey& k, const std::string& value);
// The default of an optional key as a number; std::logic_error if it has none
// the parser can take as it is.
double default_number(const SceneKey& k);

// A number as the reference prints it: whole numbers below 1e8 in full,
// others in the shortest form with a bare exponent (1e-12, 2e8).
std::string key_number_text(double v);

// While one exists (per thread), every scene_key() lookup is recorded as
// "table.key": what a test uses to see which entries a parse reaches.
class SceneKeyTrace {
 public:
  SceneKeyTrace();
  ~SceneKeyTrace();
  SceneKeyTrace(const SceneKeyTrace&) = delete;
  SceneKeyTrace& operator=(const SceneKeyTrace&) = delete;
  const std::set<std::string>& keys() const { return keys_; }

 private:
  std::set<std::string> keys_;
  SceneKeyTrace* outer_;
};

}  // namespace railcosim
