// Numbers in messages with the fewest significant digits that read back as the same double
// (0.3000001, not 0.3; 0.1, not 0.10000000000000001), in printf's %g style (0.0008, 2e-05,
// 1e+300): a bound or a value a user may copy back.
#pragma once
#include <charconv>
#include <string>
#include <string_view>

namespace tsubu {

inline std::string format_number(double v) {
  char text[32];
  const char* end = std::to_chars(text, text + sizeof text, v, std::chars_format::scientific).ptr;  // shortest
  const std::string_view shortest(text, static_cast<std::size_t>(end - text));
  int digits = 0;
  for (char c : shortest.substr(0, shortest.find('e'))) digits += c >= '0' && c <= '9';
  if (digits == 0) return std::string(shortest);  // inf, nan
  end = std::to_chars(text, text + sizeof text, v, std::chars_format::general, digits).ptr;
  return std::string(text, static_cast<std::size_t>(end - text));
}

}  // namespace tsubu
