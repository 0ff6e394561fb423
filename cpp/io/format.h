// printf-style formatting into a std::string (for log lines and messages),
// and the missing number of tables and results.
#pragma once

#include <cstdio>
#include <limits>
#include <string>

namespace nct::io
{

/// The text of std::snprintf(fmt, args...).
std::string format(const char* fmt, auto... args)
{
  std::string text(std::snprintf(nullptr, 0, fmt, args...), '\0');
  std::snprintf(text.data(), text.size() + 1, fmt, args...);
  return text;
}

/// A missing number (a case or run that gave none): NaN, "nan" in a table,
/// null in JSON.
inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();

} // namespace nct::io
