// Text that came from a file or a server, shown on a terminal: a project, plant or login
// name, a message quoting one. Control characters (C0, DEL, C1) and the bidirectional
// overrides are escaped, so a name cannot move the cursor, clear the screen, set the title or
// reorder what follows it; bytes that are not UTF-8 are shown as \xNN. JSON output needs
// none of this (the JSON writer escapes control characters itself).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace leafdig::cli {

// `keepLines`: a message's own line breaks and tabs stay (libpq's messages have them).
inline std::string terminalText(const std::string& text, bool keepLines = false) {
  std::string out;
  out.reserve(text.size());
  const auto hex = [&](unsigned char c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", c);
    out += buf;
  };
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (keepLines && (c == '\n' || c == '\t')) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    if (c < 0x20 || c == 0x7f) {
      if (c == '\n')
        out += "\\n";
      else if (c == '\t')
        out += "\\t";
      else if (c == '\r')
        out += "\\r";
      else
        hex(c);
      ++i;
      continue;
    }
    if (c < 0x80) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // One UTF-8 sequence, or the byte alone when it is not one.
    const std::size_t n = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    bool valid = n > 0 && i + n <= text.size();
    std::uint32_t cp = n == 2 ? (c & 0x1Fu) : n == 3 ? (c & 0x0Fu) : (c & 0x07u);
    for (std::size_t k = 1; valid && k < n; ++k) {
      const auto d = static_cast<unsigned char>(text[i + k]);
      valid = (d & 0xC0) == 0x80;
      cp = (cp << 6) | (d & 0x3Fu);
    }
    if (valid && ((n == 2 && cp < 0x80) || (n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000) || cp > 0x10FFFF ||
                  (cp >= 0xD800 && cp <= 0xDFFF)))
      valid = false;
    if (!valid) {
      hex(c);
      ++i;
      continue;
    }
    // C1 controls, and the embeddings, overrides and isolates that reorder text.
    if ((cp >= 0x80 && cp <= 0x9F) || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069) ||
        cp == 0x200E || cp == 0x200F || cp == 0x061C) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "\\u{%04x}", static_cast<unsigned>(cp));
      out += buf;
    } else {
      out.append(text, i, n);
    }
    i += n;
  }
  return out;
}

// A message (an error, a server's words): line breaks and tabs kept, everything else as above.
inline std::string terminalMessage(const std::string& text) {
  return terminalText(text, true);
}

}  // namespace leafdig::cli
