// What a participant written against the package is told at Configure
// (docs/participant-guide-cpp.md): its interfaces as the master describes
// them, the run's settings, and its own configuration. The names are those
// of the Python SDK (sdk/python/railcosim_sdk/participant.py): Interface,
// Footprint, the run's settings, the config.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "model.hpp"  // Footprint, Quantity

namespace railcosim {

// One side of one cut, as this participant sees it (Configure.interfaces,
// docs/protocol.md §5).
struct Interface {
  std::string cut;                    // "wr", "rs" or "ss"
  std::string peer;                   // the participant on the other side
  bool upper = false;                 // true: this side is above the element
  std::vector<double> x;              // coupling point positions at t = 0, m along the track
  double speed = 0;                   // m/s the points move at (0: fixed)
  std::vector<Quantity> receives;     // per point, held (or ramped) over each macro step
  std::vector<Quantity> sends;        // per point, at every communication point
  double stiffness = 0;               // N/m: the element at the cut, per point
  double damping = 0;                 // N s/m
  double hertz_constant = 0;          // N/m^1.5 (at wr; 0 elsewhere)
  std::vector<Footprint> footprints;  // at ss one per point (in the order of x); else empty

  std::size_t n() const { return x.size(); }  // the number of coupling points
  bool receives_force() const;                // receives == {force}
  std::string describe() const;               // "ss (lower side, 40 points)", for messages
};

// The run's settings from Configure (the Python SDK's `run`).
struct RunSettings {
  double macro_step = 0;            // H, s
  double end_time = 0;              // s
  double tolerance = 0;             // m: local error bound of a micro step (adaptive steps)
  int micro_steps = 0;              // > 0: that many equal micro steps per macro step; 0: adapt
  long max_micro_steps = 0;         // the budget of one macro step (the node's limit applied)
  bool carry_acceleration = false;  // restart convention: false = consistent, true = carry
};

// A participant's own configuration: one TOML table. With `--config FILE`
// it is the table [TABLE] of that file (TABLE: --table, default the
// participant's name); without, the table the master sends in
// Configure.own_config (for a soil whose scene says [soil] model =
// "external", the scene's whole [soil] table; else nothing: empty). Every
// error it throws is a BadRequestError naming the file and the key
// ("soil.toml: key 'soil.mass': missing"), which the master shows the user
// as BAD_REQUEST.
class OwnConfig {
 public:
  // Empty; `source` says why, in messages.
  explicit OwnConfig(std::string source = "no configuration", std::string table = "");
  // Parses `text`, the table's keys as TOML; `source` and `table` name it in
  // messages. Throws BadRequestError naming `source` and the line of a
  // syntax error.
  static OwnConfig parse(const std::string& text, const std::string& source,
                         const std::string& table);
  // The table [table] of a whole TOML file's text (`path` names it); throws
  // BadRequestError naming the file and the line, or the missing table.
  static OwnConfig table_of(const std::string& file_text, const std::string& path,
                            const std::string& table);

  bool empty() const;
  const std::string& text() const { return text_; }         // the table's keys as TOML text
  const std::string& source() const { return source_; }     // the file, or "the master's scene"
  const std::string& table() const { return table_name_; }  // "soil"
  std::vector<std::string> keys() const;                    // sorted
  bool has(std::string_view key) const;
  // The value of `key`: missing, or of another type, is a BadRequestError
  // naming source and key; a number accepts an integer too.
  double number(std::string_view key) const;
  long integer(std::string_view key) const;
  bool boolean(std::string_view key) const;
  std::string string(std::string_view key) const;
  std::vector<double> numbers(std::string_view key) const;  // an array of numbers
  // The same with a default for a missing key (another type still throws).
  double number(std::string_view key, double fallback) const;
  // "soil.toml: key 'soil.mass'": how a message names a key.
  std::string where(std::string_view key) const;

 private:
  struct Table;
  std::string text_;
  std::string source_;
  std::string table_name_;
  std::shared_ptr<const Table> table_;
};

// Everything a participant is given at Configure, once per session.
struct ParticipantSetup {
  std::string participant;            // the participant served ("soil")
  std::vector<Interface> interfaces;  // inputs and outputs come in this order
  RunSettings run;
  OwnConfig config;
};

}  // namespace railcosim
