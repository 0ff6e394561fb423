// Numeric CSV tables (puff tables, radial profiles, inlet profiles): a
// fixed header, then rows of N finite numbers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace nct::io
{

/// The rows of a CSV table and the line number of each.
template <std::size_t N>
struct Rows
{
  std::vector<std::array<double, N>> values;
  std::vector<int> lines;
};

/// Throws std::invalid_argument "file:line: what".
[[noreturn]] inline void csv_error(const std::filesystem::path& file, int line,
                                   const std::string& what)
{
  throw std::invalid_argument(file.string() + ":" + std::to_string(line) + ": " + what);
}

/// Read `file` (a `what`, for the messages): the first line must be
/// `header` (spaces ignored), every other non-blank line N finite numbers;
/// at least one row. Throws std::invalid_argument naming the file and line.
template <std::size_t N>
Rows<N> read_csv(const std::filesystem::path& file, const std::string& header,
                 const std::string& what)
{
  static const char* count[] = {"zero", "one", "two", "three", "four", "five"};
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() + ": cannot open the " + what);
  std::string text;
  if (!std::getline(in, text))
    csv_error(file, 1, "empty file; expected the header " + header);
  text.erase(std::remove_if(text.begin(), text.end(), ::isspace), text.end());
  if (text != header)
    csv_error(file, 1, "header '" + text + "'; expected " + header);
  Rows<N> rows;
  for (int line = 2; std::getline(in, text); ++line)
  {
    if (std::all_of(text.begin(), text.end(), ::isspace))
      continue;
    std::array<double, N> v;
    std::istringstream row(text);
    bool ok = true;
    for (std::size_t i = 0; i < N && ok; ++i)
    {
      std::string cell;
      ok = static_cast<bool>(std::getline(row, cell, ','));
      std::size_t end = 0;
      try
      {
        v[i] = std::stod(cell, &end);
      }
      catch (const std::exception&)
      {
        ok = false;
      }
      ok = ok && std::isfinite(v[i])
           && std::all_of(cell.begin() + static_cast<std::ptrdiff_t>(end), cell.end(), ::isspace);
    }
    std::string rest;
    if (!ok || std::getline(row, rest))
      csv_error(file, line, "'" + text + "' is not " + (N < 6 ? count[N] : std::to_string(N))
                                + " finite numbers " + header);
    rows.values.push_back(v);
    rows.lines.push_back(line);
  }
  if (rows.values.empty())
    csv_error(file, 2, "no rows after the header");
  return rows;
}

} // namespace nct::io
