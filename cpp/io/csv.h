// Numeric CSV tables (puff tables, radial profiles, inlet profiles, a
// study's design): a header, then rows of finite numbers.
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

/// A CSV table of numbers: its column names and rows.
struct NumberTable
{
  std::vector<std::string> header;        ///< column names, spaces removed
  std::vector<std::vector<double>> rows;  ///< each as wide as the header
  std::vector<int> lines;                 ///< each row's line in the file
};

/// Read `file` (a `what`, for the messages): the first line is the
/// header, `header` itself when given (spaces ignored), every other
/// non-blank line as many finite numbers as it has columns; at least one
/// row. Throws std::invalid_argument naming the file and line.
inline NumberTable read_number_table(const std::filesystem::path& file, const std::string& what,
                                     const std::string& header = "")
{
  static const char* count[] = {"zero", "one", "two", "three", "four", "five"};
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() + ": cannot open the " + what);
  std::string text;
  if (!std::getline(in, text))
    csv_error(file, 1,
              "empty file; expected " + (header.empty() ? "a header" : "the header " + header));
  text.erase(std::remove_if(text.begin(), text.end(), ::isspace), text.end());
  if (!header.empty() && text != header)
    csv_error(file, 1, "header '" + text + "'; expected " + header);
  NumberTable t;
  std::istringstream names(text);
  for (std::string name; std::getline(names, name, ',');)
    t.header.push_back(name);
  const std::size_t n = t.header.size();
  for (int line = 2; std::getline(in, text); ++line)
  {
    if (std::all_of(text.begin(), text.end(), ::isspace))
      continue;
    std::vector<double> v(n);
    std::istringstream row(text);
    bool ok = true;
    for (std::size_t i = 0; i < n && ok; ++i)
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
      csv_error(file, line, "'" + text + "' is not "
                                + (n == 1  ? std::string("a finite number ")
                                   : n < 6 ? count[n] + std::string(" finite numbers ")
                                           : std::to_string(n) + " finite numbers ")
                                + (header.empty() ? names.str() : header));
    t.rows.push_back(std::move(v));
    t.lines.push_back(line);
  }
  if (t.rows.empty())
    csv_error(file, 2, "no rows after the header");
  return t;
}

/// Read `file` (a `what`, for the messages): the first line must be
/// `header` (spaces ignored), every other non-blank line N finite numbers;
/// at least one row. Throws std::invalid_argument naming the file and line.
template <std::size_t N>
Rows<N> read_csv(const std::filesystem::path& file, const std::string& header,
                 const std::string& what)
{
  const NumberTable t = read_number_table(file, what, header);
  if (t.header.size() != N)
    throw std::logic_error("read_csv<" + std::to_string(N) + ">: header " + header);
  Rows<N> rows;
  for (const auto& r : t.rows)
  {
    std::array<double, N> v;
    std::copy(r.begin(), r.end(), v.begin());
    rows.values.push_back(v);
  }
  rows.lines = t.lines;
  return rows;
}

} // namespace nct::io
