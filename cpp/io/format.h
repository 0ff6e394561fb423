// printf-style formatting into a std::string (for log lines and messages).
#pragma once

#include <cstdio>
#include <string>

namespace nct::io
{

/// The text of std::snprintf(fmt, args...), up to 511 characters.
std::string format(const char* fmt, auto... args)
{
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

} // namespace nct::io
