#include "remote/peer_text.hpp"

#include <cstdint>
#include <cstdio>

namespace railcosim::remote {

namespace {

void hex_escape(std::string& out, unsigned char byte) {
  char e[5];
  std::snprintf(e, sizeof e, "\\x%02x", byte);
  out += e;
}

// The length of the valid UTF-8 sequence at `s[k]` (2 to 4) and its code
// point, or 0 when the bytes there are not one.
std::size_t utf8_sequence(std::string_view s, std::size_t k, std::uint32_t& cp) {
  const auto b = static_cast<unsigned char>(s[k]);
  std::size_t n = 0;
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
    cp = b & 0x1F;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    cp = b & 0x0F;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    cp = b & 0x07;
  } else {
    return 0;
  }
  if (k + n > s.size()) return 0;
  for (std::size_t i = 1; i < n; ++i) {
    const auto c = static_cast<unsigned char>(s[k + i]);
    if ((c & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (c & 0x3F);
  }
  // Overlong forms, surrogates and code points past U+10FFFF.
  if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)) ||
      (cp >= 0xD800 && cp <= 0xDFFF))
    return 0;
  return n;
}

// The C1 controls and the code points that reorder or hide what follows.
bool inert_code_point(std::uint32_t cp) {
  return (cp >= 0x80 && cp <= 0x9F) || (cp >= 0x202A && cp <= 0x202E) ||
         (cp >= 0x2066 && cp <= 0x2069) || cp == 0x2028 || cp == 0x2029;
}

}  // namespace

std::string terminal_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size();) {
    const auto b = static_cast<unsigned char>(text[k]);
    if (b >= 0x20 && b < 0x7F) {
      out += static_cast<char>(b);
      ++k;
    } else if (b == '\n') {
      out += "\\n";
      ++k;
    } else if (b == '\r') {
      out += "\\r";
      ++k;
    } else if (b == '\t') {
      out += "\\t";
      ++k;
    } else if (std::uint32_t cp = 0; b >= 0x80 && utf8_sequence(text, k, cp) > 0) {
      const std::size_t n = utf8_sequence(text, k, cp);
      if (inert_code_point(cp)) {
        char e[8];
        std::snprintf(e, sizeof e, "\\u%04x", static_cast<unsigned>(cp));
        out += e;
      } else {
        out.append(text.substr(k, n));
      }
      k += n;
    } else {
      hex_escape(out, b);
      ++k;
    }
  }
  return out;
}

std::string markdown_text(std::string_view text) {
  const std::string line = terminal_text(text);
  std::string out;
  out.reserve(line.size());
  for (const char c : line) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '\\':
      case '`':
      case '|':
      case '[':
      case ']':
      case '!':
      case '#':
        out += '\\';
        out += c;
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace railcosim::remote
