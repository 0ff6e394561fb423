#include "io/toml_input.h"

#include <algorithm>
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

int integer(const toml::table& t, const std::string& section, const std::string& key, long def,
            long lo, long hi, const fs::path& file)
{
  const toml::node* n = t[key].node();
  if (!n)
    return int(def);
  auto v = n->value_exact<int64_t>();
  if (!v || *v < lo || *v > hi)
    throw key_error(file, section + "." + key,
                    format("an integer in [%ld, %ld], got ", lo, hi) + literal(*n));
  return int(*v);
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

void refuse_unknown_keys(const toml::table& t, const std::set<std::string>& known,
                         const fs::path& file, const std::string& where,
                         const std::string& table, KeyErrors& errors)
{
  for (auto&& [k, v] : t)
    if (!known.count(std::string(k.str())))
    {
      std::string list;
      for (auto& n : known)
        list += (list.empty() ? "" : ", ") + n;
      errors.add(key_error(file, where + std::string(k.str()),
                           "unknown key; " + table + " takes " + list)
                     .what());
    }
}

void KeyErrors::add(const std::string& message)
{
  // The same problem twice (every case of a study met the base scene's): once.
  if (std::find(_seen.begin(), _seen.end(), message) != _seen.end())
    return;
  _seen.push_back(message);
  const std::string head = _file.string() + ": key '";
  if (message.rfind(head, 0) != 0)
  {
    const std::string prefix = _file.string() + ": ";
    _errors.add(message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message);
    return;
  }
  const std::string rest = message.substr(_file.string().size() + 2);
  const std::string key = rest.substr(5, rest.find('\'', 5) - 5);
  // "factor[2].levels" (counted from 1) is the TOML path "factor[1].levels".
  std::string path;
  for (std::size_t i = 0; i < key.size(); ++i)
  {
    if (key[i] == '[')
    {
      const std::size_t end = key.find(']', i);
      path += "[" + std::to_string(std::stoul(key.substr(i + 1, end - i - 1)) - 1) + "]";
      i = end;
    }
    else
      path += key[i];
  }
  // The key itself, else the nearest table that holds it.
  const toml::node* node = nullptr;
  for (std::string p = path; !p.empty() && !node;)
  {
    node = _table.at_path(p).node();
    const auto cut = p.find_last_of(".[");
    p = cut == std::string::npos ? "" : p.substr(0, cut);
  }
  const int line = node ? static_cast<int>(node->source().begin.line) : 0;
  _errors.add(line > 0 ? _file.string() + ":" + std::to_string(line) : _file.string(), line,
              rest);
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
