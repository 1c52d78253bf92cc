#include "toml_nesting.hpp"

#include <vector>

#include "scene_error.hpp"

namespace railcosim {
namespace {

class NestingScan {
 public:
  NestingScan(const std::string& text, const std::string& source) : s_(text), source_(source) {}
  void run();

 private:
  struct Open {
    char kind;  // '[' array, '{' inline table
    int depth;  // the levels down to and including this one
  };
  void check(int depth, const char* what) const;
  void skip_string();
  void skip_comment();
  void header();
  void value_open(char c);
  void close();

  const std::string& s_;
  const std::string& source_;
  std::size_t i_ = 0;
  long line_ = 1;
  std::vector<Open> open_;
  int header_ = 0;      // the parts of the last table header
  bool in_key_ = true;  // reading a key (not a value)
  bool key_start_ = true;
  int key_parts_ = 0;
  int value_depth_ = 0;  // the depth of the value being read
};

void NestingScan::check(int depth, const char* what) const {
  if (depth > kMaxTomlNesting)
    throw SceneError(source_ + ":" + std::to_string(line_) + ": " + what + " nests " +
                     std::to_string(depth) + " levels deep or more; at most " +
                     std::to_string(kMaxTomlNesting) +
                     " are allowed (table header parts, dotted key parts, arrays and inline "
                     "tables together)");
}

void NestingScan::skip_string() {
  const char q = s_[i_];
  const bool triple = s_.compare(i_, 3, std::string(3, q)) == 0;
  i_ += triple ? 3 : 1;
  while (i_ < s_.size()) {
    const char c = s_[i_];
    if (c == '\n') {
      ++line_;
      if (!triple) return;  // the parser reports the unterminated string
    }
    if (c == '\\' && q == '"') {
      if (i_ + 1 < s_.size() && s_[i_ + 1] == '\n') ++line_;
      i_ += 2;
      continue;
    }
    if (c == q && (!triple || s_.compare(i_, 3, std::string(3, q)) == 0)) {
      i_ += triple ? 3 : 1;
      // A closing triple quote may be followed by up to two more quotes.
      while (triple && i_ < s_.size() && s_[i_] == q) ++i_;
      return;
    }
    ++i_;
  }
}

void NestingScan::skip_comment() {
  while (i_ < s_.size() && s_[i_] != '\n') ++i_;
}

// [a.b."c.d"] or [[a.b]]: one level per part.
void NestingScan::header() {
  int parts = 1;
  i_ += 1;
  while (i_ < s_.size() && s_[i_] != '\n' && s_[i_] != ']') {
    if (s_[i_] == '"' || s_[i_] == '\'') {
      skip_string();
      continue;
    }
    if (s_[i_] == '.') check(++parts, "a table header");
    ++i_;
  }
  header_ = parts;
}

void NestingScan::value_open(char c) {
  const int depth =
      (open_.empty() || open_.back().kind == '{' ? value_depth_ : open_.back().depth) + 1;
  check(depth, c == '[' ? "an array" : "an inline table");
  open_.push_back({c, depth});
  in_key_ = c == '{';
  key_start_ = true;
  ++i_;
}

void NestingScan::close() {
  if (!open_.empty()) open_.pop_back();
  in_key_ = false;
  ++i_;
}

void NestingScan::run() {
  while (i_ < s_.size()) {
    const char c = s_[i_];
    if (c == '\n') {
      ++line_;
      ++i_;
      if (open_.empty()) in_key_ = key_start_ = true;
    } else if (c == ' ' || c == '\t' || c == '\r') {
      ++i_;
    } else if (c == '#') {
      skip_comment();
    } else if (in_key_ && key_start_ && open_.empty() && c == '[') {
      header();
      in_key_ = false;  // the rest of the line is a comment or nothing
    } else if (in_key_) {
      const int base = open_.empty() ? header_ : open_.back().depth;
      if (key_start_ && c != '}') {
        key_parts_ = 1, key_start_ = false;
        check(base + 1, "a key");
      }
      if (c == '"' || c == '\'') {
        skip_string();
        continue;
      }
      if (c == '.') check(base + ++key_parts_, "a dotted key");
      if (c == '=') in_key_ = false, value_depth_ = base + key_parts_;
      if (c == '}') {
        close();
        continue;
      }
      ++i_;
    } else if (c == '"' || c == '\'') {
      skip_string();
    } else if (c == '[' || c == '{') {
      value_open(c);
    } else if (c == ']' || c == '}') {
      close();
    } else if (c == ',' && !open_.empty() && open_.back().kind == '{') {
      in_key_ = key_start_ = true;
      ++i_;
    } else {
      ++i_;
    }
  }
}

}  // namespace

void check_toml_nesting(const std::string& text, const std::string& source) {
  NestingScan(text, source).run();
}

}  // namespace railcosim
