// How deep a TOML text nests, measured before the text is parsed: a dotted
// key, a table header, an array or an inline table thousands of levels deep
// would make the parser (and whatever walks its tree) recurse once per
// level until the stack runs out. The scan reads the text once, in order,
// and keeps no more than the open arrays and inline tables.
#pragma once

#include <string>

namespace railcosim {

// The deepest nesting a scene (or any TOML text the programs read) may have:
// a table header's parts plus a key's parts plus the arrays and inline
// tables around a value. The scenes use at most 3.
inline constexpr int kMaxTomlNesting = 32;

// Throws SceneError "SOURCE:LINE: ..." at the first place where `text`
// nests deeper than kMaxTomlNesting. Says nothing about anything else (the
// parser judges the syntax).
void check_toml_nesting(const std::string& text, const std::string& source);

}  // namespace railcosim
