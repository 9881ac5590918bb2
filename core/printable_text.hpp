// Text that came from outside (a client's request, a file name it named), made safe to put in
// an error message or a log line: a control character (a NUL, a line end, an escape sequence)
// would cut a message at the NUL, split one log line into two or forge a line of its own.
#pragma once

#include <string>
#include <string_view>

namespace tofcomp::core {

// `text` with every control character (bytes 0x00-0x1F and 0x7F) written as an escape:
// \n, \r and \t by name, the others as \xNN. Every other byte is kept as it is.
// Inline: the client library builds the protocol's parser without the rest of core.
inline std::string printable(std::string_view text) {
  constexpr unsigned char kFirstPrintable = 0x20;
  constexpr unsigned char kDelete = 0x7F;
  constexpr std::string_view kHexDigits = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= kFirstPrintable && byte != kDelete) {
      out.push_back(c);
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      out += "\\x";
      out.push_back(kHexDigits[byte >> 4]);
      out.push_back(kHexDigits[byte & 0xF]);
    }
  }
  return out;
}

}  // namespace tofcomp::core
