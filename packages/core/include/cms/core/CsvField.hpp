#pragma once

#include <string>

namespace cms {

/// One CSV field (RFC 4180): quoted, with "" for ", when it holds a comma,
/// a quote or a line break; as it is otherwise. Every table the project
/// writes quotes names through it (a substructure named "blade, stage 1"
/// shifted the Campbell CSV's columns by one; found by a review).
inline std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) {
    if (c == '"') o += '"';
    o += c;
  }
  return o + "\"";
}

}  // namespace cms
