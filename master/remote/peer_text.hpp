// A node's words (its error messages, the reason its window ended, the peer
// it says it waits for) are a peer's, not the master's: before they reach a
// terminal or a Markdown report they are made inert. One function per
// medium, used wherever such words are shown.
#pragma once

#include <string>
#include <string_view>

namespace railcosim::remote {

// `text` on one line and with no control sequence: every C0 control byte
// (newline and carriage return included), DEL, the C1 controls (as bytes
// and as UTF-8), the bidirectional overrides and any byte that is not part
// of valid UTF-8 become a visible escape (`\n`, `\r`, `\t`, `\x1b`,
// `\u202e`); printable text, UTF-8 included, is kept. Backslashes are kept
// as they are, so the function is idempotent: what it returns, it returns
// unchanged.
std::string terminal_text(std::string_view text);

// `text` as inert Markdown for a table cell or a line of prose:
// terminal_text() first (so a row cannot break), then every character that
// breaks a table row or starts a heading, a link, an image, a code span or
// an HTML tag is escaped: `\`, `` ` ``, `|`, `[`, `]`, `!`, `#` with a
// backslash, `<`, `>`, `&` as entities. (Emphasis marks are left: they
// cannot reach outside the text, and statuses such as `not_run` stay
// searchable.)
std::string markdown_text(std::string_view text);

}  // namespace railcosim::remote
