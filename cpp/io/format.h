// printf-style formatting into a std::string (for log lines and messages).
#pragma once

#include <cstdio>
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

} // namespace nct::io
