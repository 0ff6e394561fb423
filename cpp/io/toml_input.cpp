#include "io/toml_input.h"

#include <charconv>
#include <cmath>
#include <regex>
#include <sstream>

#include "io/format.h"

namespace nct::io
{
namespace fs = std::filesystem;

scene::Error key_error(const fs::path& file, const std::string& key, const std::string& what)
{
  return scene::Error(file.string() + ": key '" + key + "': " + what);
}

toml::table parse_toml(const fs::path& file, const std::string& what)
{
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw scene::Error(file.string() + ": " + what + " not found");
  try
  {
    return toml::parse_file(file.string());
  }
  catch (const toml::parse_error& e)
  {
    throw scene::Error(file.string() + format(":%u:%u: not valid TOML: ", e.source().begin.line,
                                              e.source().begin.column)
                       + std::string(e.description()));
  }
}

std::string literal(double x)
{
  char text[64];
  std::string out(text, std::to_chars(text, text + sizeof text, x).ptr);
  if (std::isfinite(x) && out.find_first_of(".e") == std::string::npos)
    out += ".0";
  return out;
}

std::string literal(const toml::node& v)
{
  if (auto x = v.value_exact<double>())
    return literal(*x);
  std::ostringstream out;
  v.visit([&](auto&& x) { out << x; });
  return out.str();
}

std::vector<std::string> string_list(const toml::node& v, const fs::path& file,
                                     const std::string& key, bool one_allowed)
{
  std::vector<std::string> out;
  if (one_allowed && v.is_string())
    return {*v.value<std::string>()};
  const auto* a = v.as_array();
  if (!a)
    throw key_error(file, key, one_allowed ? "expected a string or an array of strings"
                                           : "expected an array of strings");
  for (auto&& e : *a)
  {
    if (!e.is_string())
      throw key_error(file, key, "expected strings, got " + literal(e));
    out.push_back(*e.value<std::string>());
  }
  return out;
}

void only(const toml::table& t, const std::set<std::string>& known, const fs::path& file,
          const std::string& where, const std::string& table)
{
  for (auto&& [k, v] : t)
    if (!known.count(std::string(k.str())))
    {
      std::string list;
      for (auto& n : known)
        list += (list.empty() ? "" : ", ") + n;
      throw key_error(file, where + std::string(k.str()), "unknown key; " + table + " takes "
                                                              + list);
    }
}

fs::path file_path(const fs::path& file, const std::string& key, const toml::node* node,
                   const std::string& what)
{
  auto path = node ? node->value_exact<std::string>() : std::nullopt;
  if (!path)
    throw key_error(file, key, node ? "expected a string (" + what + ", relative to "
                                          + file.filename().string() + "), got " + literal(*node)
                                    : "missing or not a string: " + what);
  fs::path out = fs::path(*path).is_absolute() ? fs::path(*path) : file.parent_path() / *path;
  std::error_code ec;
  if (!fs::is_regular_file(out, ec))
    throw key_error(file, key, what + " " + out.string() + " not found");
  return out;
}

void check_name(const fs::path& file, const std::string& key, const std::string& name,
                const std::string& labels)
{
  static const std::regex ok("[A-Za-z0-9_.+-]+");
  if (!std::regex_match(name, ok))
    throw key_error(file, key, "'" + name + "': letters, digits and _.+- only (it names "
                                   + labels + ")");
}

} // namespace nct::io
