#include "scene/scene.h"
#include "scene/visitor.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

namespace nct::scene
{
namespace
{

/// Levenshtein distance, for "did you mean" hints.
std::size_t edit_distance(const std::string& a, const std::string& b)
{
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
  {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
    {
      std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1,
                         diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

/// Does a declared name (with "*" segments) match a concrete dotted path?
bool matches(const std::string& pattern, const std::string& name)
{
  std::istringstream p(pattern), n(name);
  std::string ps, ns;
  while (true)
  {
    bool more_p = static_cast<bool>(std::getline(p, ps, '.'));
    bool more_n = static_cast<bool>(std::getline(n, ns, '.'));
    if (!more_p || !more_n)
      return more_p == more_n;
    if (ps != "*" && ps != ns)
      return false;
  }
}

std::string kind_name(const Key& key)
{
  switch (key.kind)
  {
  case Kind::boolean:
    return "true or false";
  case Kind::integer:
    return "an integer";
  case Kind::real:
    return "a number";
  case Kind::choice:
    return "a string";
  case Kind::string:
    return "a string";
  case Kind::strings:
    return "an array of strings";
  case Kind::reals:
    return "an array of numbers";
  case Kind::points:
    return "an array of [x, y, z] points";
  case Kind::options:
    return "a table of name = value options";
  }
  return "";
}

std::string format_number(double x)
{
  std::ostringstream s;
  s << x;
  return s.str();
}

/// "what is accepted" for a key, e.g. "an integer in [1, 12]".
std::string accepted(const Key& key)
{
  std::string what = kind_name(key);
  if (key.kind == Kind::choice)
  {
    what = "one of";
    for (std::size_t i = 0; i < key.choices.size(); ++i)
      what += (i ? ", \"" : " \"") + key.choices[i] + "\"";
  }
  else if (key.kind == Kind::integer || key.kind == Kind::real || key.kind == Kind::reals)
  {
    bool lo = std::isfinite(key.min), hi = std::isfinite(key.max);
    if (lo && hi)
      what += std::string(key.kind == Kind::reals ? ", each" : "") + " in ["
              + format_number(key.min) + ", " + format_number(key.max) + "]";
    else if (lo)
      what += " >= " + format_number(key.min);
    else if (hi)
      what += " <= " + format_number(key.max);
  }
  if (!key.unit.empty())
    what += " [" + key.unit + "]";
  return what;
}

/// A number node as a double (toml++'s value<double>() refuses integers
/// beyond 2^53, e.g. 9007199254740993).
double number(const toml::node& n)
{
  if (const auto* i = n.as_integer())
    return static_cast<double>(i->get());
  return n.as_floating_point()->get();
}

std::string source_text(const toml::node& n)
{
  std::ostringstream s;
  if (auto* str = n.as_string())
    s << '"' << str->get() << '"';
  else if (n.is_table())
    s << "a table";
  else
    n.visit([&](auto&& v) { s << v; });
  return s.str();
}

/// Where a value came from: "file:line" or the --set option, and its line
/// (-1: a --set option, 0: none).
std::pair<std::string, int> source_of(const toml::node& n, const std::string& file)
{
  const auto& src = n.source();
  if (src.path && src.path->rfind("--set", 0) == 0)
    return {*src.path, -1};
  if (src.begin.line > 0)
    return {(src.path ? *src.path : file) + ":" + std::to_string(src.begin.line),
            static_cast<int>(src.begin.line)};
  return {file, 0};
}

/// Add a problem at a node's source.
void add_at(Errors& errors, const toml::node& n, const std::string& file,
            const std::string& message)
{
  const auto [where, line] = source_of(n, file);
  errors.add(where, line, message);
}

/// A problem unless a user value fits its declared key; false if refused.
bool check_value(const Key& key, const std::string& name, const toml::node& n,
                 const std::string& file, Errors& errors)
{
  auto fail = [&](const std::string& why)
  {
    add_at(errors, n, file, "key '" + name + "': " + why + "; expected " + accepted(key));
    return false;
  };
  switch (key.kind)
  {
  case Kind::boolean:
    return n.is_boolean() || fail("got " + source_text(n));
  case Kind::integer:
  {
    if (!n.is_integer())
      return fail("got " + source_text(n));
    double v = static_cast<double>(n.as_integer()->get());
    return (v >= key.min && v <= key.max) || fail("got " + source_text(n) + ", out of range");
  }
  case Kind::real:
  {
    if (!n.is_number())
      return fail("got " + source_text(n));
    double v = number(n);
    // Infinity only where the range is unbounded above (e.g. a width).
    const bool infinite_ok = v > 0 && std::isinf(v) && std::isinf(key.max);
    if (std::isnan(v) || (!std::isfinite(v) && !infinite_ok) || v < key.min || v > key.max)
      return fail("got " + source_text(n) + ", out of range");
    return true;
  }
  case Kind::choice:
    if (!n.is_string())
      return fail("got " + source_text(n));
    if (std::find(key.choices.begin(), key.choices.end(), n.as_string()->get())
        == key.choices.end())
      return fail("got " + source_text(n) + ", not a known choice");
    return true;
  case Kind::string:
    return n.is_string() || fail("got " + source_text(n));
  case Kind::strings:
    if (!n.is_array() || !n.as_array()->is_homogeneous(toml::node_type::string))
      if (!(n.is_array() && n.as_array()->empty()))
        return fail("got " + source_text(n));
    return true;
  case Kind::reals:
  {
    bool ok = n.is_array();
    if (ok)
      for (const auto& x : *n.as_array())
        ok = ok && x.is_number() && std::isfinite(number(x)) && number(x) >= key.min
             && number(x) <= key.max;
    return ok || fail("got " + source_text(n));
  }
  case Kind::points:
  {
    bool ok = n.is_array();
    if (ok)
      for (const auto& p : *n.as_array())
      {
        const auto* a = p.as_array();
        ok = ok && a && a->size() == 3;
        if (ok)
          for (const auto& c : *a)
            ok = ok && c.is_number() && std::isfinite(number(c));
      }
    return ok || fail("got " + source_text(n));
  }
  case Kind::options:
    if (!n.is_table())
      return fail("got " + source_text(n));
    for (auto&& [k, v] : *n.as_table())
      if (!(v.is_string() || v.is_number() || v.is_boolean()))
        return fail("option '" + std::string(k.str()) + "' is not a string, number or boolean");
    return true;
  }
  return true;
}

const Key* find_key(const std::string& name)
{
  // Exact names win over wildcards (material.cornea.c10 over material.*.c10).
  for (const Key& k : keys())
    if (k.name == name)
      return &k;
  for (const Key& k : keys())
    if (matches(k.name, name))
      return &k;
  return nullptr;
}

std::string suggestion(const std::string& name)
{
  const Key* best = nullptr;
  std::size_t best_d = 4;
  for (const Key& k : keys())
  {
    // The distance is at least the difference in length (a long name
    // would take seconds).
    if (std::max(k.name.size(), name.size()) - std::min(k.name.size(), name.size()) >= best_d)
      continue;
    std::size_t d = edit_distance(k.name, name);
    if (d < best_d)
      best = &k, best_d = d;
  }
  return best ? " (did you mean '" + best->name + "'?)" : "";
}

/// Does a table of this name hold declared keys (material, material.cornea)?
bool declared_table(const std::string& name)
{
  const auto levels = std::count(name.begin(), name.end(), '.') + 1;
  for (const Key& k : keys())
  {
    // the key's first `levels` segments
    std::size_t end = 0;
    for (long l = 0; l < levels && end != std::string::npos; ++l)
      end = k.name.find('.', l == 0 ? 0 : end + 1);
    if (end != std::string::npos && matches(k.name.substr(0, end), name))
      return true;
  }
  return false;
}

/// The first leaf under a node (itself if a value or an empty table); its
/// dotted name is appended to `name`. Errors about a table point there
/// (tables made by --set have no source of their own).
const toml::node& first_leaf(const toml::node& n, std::string& name)
{
  const toml::node* leaf = &n;
  while (leaf->is_table() && !leaf->as_table()->empty())
  {
    auto first = leaf->as_table()->begin();
    name.append(".").append(first->first.str());
    leaf = &first->second;
  }
  return *leaf;
}

/// Keys renamed since an earlier version: old name, new name, what else changed.
const std::vector<std::array<const char*, 3>>& renamed()
{
  static const std::vector<std::array<const char*, 3>> names = {
      {"air.inlet_velocity", "inlet.velocity", ""},
      {"air.inlet_profile", "inlet.profile", " (\"plug\" is now \"uniform\")"},
      {"air.inlet_history", "inlet.history", ""},
      {"boundary.surface_load", "boundary.press", ""},
      {"air.dt", "dynamics.dt", " (one time step for every dynamic phase)"}};
  return names;
}

/// Check every leaf of a user table against the declared keys; the
/// problems into `errors`, the entries refused dropped from the table (their
/// defaults stand in) and marked there.
void check_table(toml::table& t, const std::string& prefix, const std::string& file,
                 Errors& errors)
{
  std::vector<std::string> drop;
  for (auto&& [k, v] : t)
  {
    const std::string part(k.str());
    std::string name = prefix.empty() ? part : prefix + "." + part;
    // Names are joined with '.' and looked up as paths ("x[0]" indexes);
    // "*" stands for any name in the declared keys.
    if (part.empty() || part.find_first_of(".[]*") != std::string::npos)
    {
      std::string leaf_name;
      add_at(errors, first_leaf(v, leaf_name), file,
             "key '" + name + "': the name \"" + part + "\" is empty or holds '.', '[', ']' or '*'");
      errors.refuse(name);
      drop.push_back(part);
      continue;
    }
    const Key* key = find_key(name);
    if (key)
    {
      if (!check_value(*key, name, v, file, errors)) // a table too: wrong type
      {
        errors.refuse(name);
        drop.push_back(part);
      }
      continue;
    }
    if (v.is_table() && declared_table(name))
    {
      check_table(*v.as_table(), name, file, errors);
      continue;
    }
    // Unknown: name its first leaf (zero_presure.enabled), or the empty table.
    const toml::node& leaf = first_leaf(v, name);
    errors.refuse(name);
    drop.push_back(part);
    const auto& r = renamed();
    auto old = std::find_if(r.begin(), r.end(), [&](const auto& n) { return name == n[0]; });
    if (old != r.end())
      add_at(errors, leaf, file,
             "key '" + name + "' is now '" + (*old)[1] + "'" + (*old)[2] + "; rename it");
    else
      add_at(errors, leaf, file,
             "unknown key '" + name + "'" + suggestion(name) + "; 'nct describe' lists every key");
  }
  for (const auto& part : drop)
    t.erase(part);
}

/// Insert `value` at a dotted path, creating tables on the way.
void insert_at(toml::table& t, const std::string& name, toml::node&& value,
               const std::string& where)
{
  auto dot = name.find('.');
  std::string head = name.substr(0, dot);
  if (dot == std::string::npos)
  {
    t.insert_or_assign(head, std::move(value));
    return;
  }
  auto* sub = t.get(head);
  if (!sub)
    sub = &t.insert(head, toml::table{}).first->second;
  if (!sub->is_table())
    throw Error(where + ": '" + head + "' is not a table");
  insert_at(*sub->as_table(), name.substr(dot + 1), std::move(value), where);
}

toml::table parse_literal(const std::string& literal,
                          const std::string& where)
{
  toml::table t;
  try
  {
    t = toml::parse("v = " + literal, where);
  }
  catch (const toml::parse_error&)
  {
    // Bare words are strings: --set mesh.source=file
    try
    {
      t = toml::parse("v = \"" + literal + "\"", where);
    }
    catch (const toml::parse_error&)
    {
      throw Error(where + ": '" + literal + "' is neither a TOML value nor a bare word");
    }
  }
  if (t.size() != 1) // "5\nfoo = 1"
    throw Error(where + ": more than one value after '='");
  return t;
}

/// toml++ recurses once per level of nested tables in its parser and
/// overflows the stack near 30000 levels (a.a.a... = 1); a scene's keys
/// nest 3 deep. Refuse text that could nest far deeper before parsing it.
void check_nesting(std::istream& in, const std::string& where)
{
  constexpr std::size_t max_dots = 1000;
  std::size_t line = 1, dots = 0;
  for (char c; in.get(c);)
    if (c == '\n')
      ++line, dots = 0;
    else if (c == '.' && ++dots > max_dots)
      throw Error(where + ":" + std::to_string(line) + ": more than "
                  + std::to_string(max_dots)
                  + " '.' on one line; a scene's keys nest at most 3 deep");
}

/// A scalar node as text: strings bare, booleans "true"/"false".
std::string scalar_text(const toml::node& n)
{
  if (auto* str = n.as_string())
    return str->get();
  std::ostringstream s;
  n.visit([&](auto&& v) { s << v; });
  return s.str();
}

/// Are all of a key's `when` conditions ("a=x,b=y|z") met by the user's
/// table (or the defaults)?
bool applies(const Key& key, const toml::table& user)
{
  std::istringstream conditions(key.when);
  std::string condition;
  while (std::getline(conditions, condition, ','))
  {
    auto eq = condition.find('=');
    const std::string name = condition.substr(0, eq), want = condition.substr(eq + 1);
    const toml::node* n = user.at_path(name).node();
    toml::table d;
    if (!n)
    {
      d = toml::parse("v = " + find_key(name)->default_value);
      n = d.get("v");
    }
    // "x|y": any of the choices
    const std::string have = scalar_text(*n);
    std::istringstream choices(want);
    bool any = false;
    for (std::string choice; std::getline(choices, choice, '|');)
      any = any || choice == have;
    if (!any)
      return false;
  }
  return true;
}

/// The --set option that turned a file's key off: the option that set a
/// switch of the key's `when` to a value the key does not apply at; empty
/// if none did (or the key itself is an option's).
std::string switched_off_by(const Key& key, const toml::node& value, const toml::table& user)
{
  if (source_of(value, "").second < 0)
    return "";
  std::istringstream conditions(key.when);
  for (std::string condition; std::getline(conditions, condition, ',');)
  {
    const std::string name = condition.substr(0, condition.find('='));
    const toml::node* n = user.at_path(name).node();
    if (!n || source_of(*n, "").second >= 0)
      continue;
    Key single = key;
    single.when = condition;
    if (!applies(single, user))
      return source_of(*n, "").first;
  }
  return "";
}

/// Check the `when` condition of every user key. A file's key that a
/// --set option turned off (a study's variant without the springs, say,
/// on a scene that gives their stiffness) is dropped, with a note.
void check_conditions(const toml::table& t, const std::string& prefix,
                      const toml::table& user, const std::string& file, Errors& errors,
                      std::vector<std::string>& dropped, std::vector<std::string>& notes)
{
  for (auto&& [k, v] : t)
  {
    std::string name = prefix.empty() ? std::string(k.str())
                                      : prefix + "." + std::string(k.str());
    const Key* key = find_key(name);
    if (v.is_table() && !(key && key->kind == Kind::options))
      check_conditions(*v.as_table(), name, user, file, errors, dropped, notes);
    else if (key && !applies(*key, user))
    {
      const std::string what = "key '" + name + "'"
                               + (key->name == name ? "" : " (as '" + key->name + "')")
                               + " applies only when " + key->when;
      if (const std::string option = switched_off_by(*key, v, user); !option.empty())
      {
        notes.push_back(source_of(v, file).first + ": " + what + ", which " + option
                        + " turned off: ignored");
        dropped.push_back(name);
        continue;
      }
      add_at(errors, v, file, what + "; remove it or change the scene to that");
      errors.refuse(name);
    }
  }
}

/// Remove the node at a dotted path (if there).
void erase_at(toml::table& t, const std::string& name)
{
  const auto dot = name.find('.');
  if (dot == std::string::npos)
  {
    t.erase(name);
    return;
  }
  if (auto* sub = t.get(name.substr(0, dot)); sub && sub->is_table())
    erase_at(*sub->as_table(), name.substr(dot + 1));
}

} // namespace

void Errors::add(const std::string& where, int line, const std::string& message)
{
  // The file's lines in order, then the --set options, then the file as a whole.
  const int order = line > 0 ? line : line < 0 ? std::numeric_limits<int>::max() - 1
                                               : std::numeric_limits<int>::max();
  _problems.push_back({order, _problems.size(), where + ": " + message});
}

void Errors::at(const Scene& scene, const std::string& key, const std::string& message)
{
  const auto [where, line] = scene.origin(key);
  if (where.empty())
    add(message);
  else
    add(where, line, message);
}

bool Errors::refused(const std::string& key) const
{
  return std::find(_refused.begin(), _refused.end(), key) != _refused.end();
}

void Errors::raise() const
{
  if (_problems.empty())
    return;
  auto sorted = _problems;
  std::stable_sort(sorted.begin(), sorted.end(), [](const Problem& a, const Problem& b)
                   { return a.order < b.order; });
  if (sorted.size() == 1)
    throw Error(sorted[0].text);
  std::string text = std::to_string(sorted.size()) + " problems in " + _file.string() + ":";
  for (const auto& p : sorted)
    text += "\n  " + p.text;
  throw Error(text);
}

Scene Scene::load(const std::filesystem::path& file,
                  const std::vector<std::string>& overrides)
{
  Errors errors(file);
  Scene scene = load(file, overrides, errors);
  errors.raise();
  return scene;
}

Scene Scene::load(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                  Errors& errors)
{
  const std::string fname = file.string();
  std::error_code ec; // e.g. a name too long
  if (!std::filesystem::is_regular_file(file, ec))
    throw Error((fname.empty() ? "\"\"" : fname) + ": scene file not found");
  toml::table user;
  try
  {
    std::ifstream text(file);
    check_nesting(text, fname);
    user = toml::parse_file(fname);
  }
  catch (const toml::parse_error& e)
  {
    const auto& b = e.source().begin;
    throw Error(fname + ":" + std::to_string(b.line) + ":"
                + std::to_string(b.column) + ": not valid TOML: "
                + std::string(e.description()));
  }

  for (const std::string& o : overrides)
  {
    const std::string where = "--set " + o;
    try
    {
      std::istringstream text(o);
      check_nesting(text, where);
      auto eq = o.find('=');
      if (eq == std::string::npos || eq == 0)
        throw Error(where + ": expected section.key=value");
      std::string name = o.substr(0, eq);
      toml::table parsed = parse_literal(o.substr(eq + 1), where);
      insert_at(user, name, std::move(*parsed.get("v")), where);
    }
    catch (const Error& e)
    {
      std::string message = e.what(); // "--set ...: what"
      if (message.rfind(where, 0) == 0)
        message.erase(0, message.find_first_not_of(": ", where.size()));
      errors.add(where, -1, message);
    }
  }

  // Every problem of the user's keys; the refused ones are dropped (their
  // defaults stand in), so that the checks that follow see a valid scene.
  check_table(user, "", fname, errors);
  std::vector<std::string> dropped, notes;
  check_conditions(user, "", user, fname, errors, dropped, notes);
  for (const std::string& name : errors.refused_keys())
    erase_at(user, name);
  for (const std::string& name : dropped)
    erase_at(user, name);

  // Resolved scene: declared defaults under the user's values. Wildcard
  // keys get defaults only in the tables the user wrote.
  toml::table resolved;
  auto add_default = [&](const Key& key, const std::string& name)
  {
    toml::table d = toml::parse("v = " + key.default_value);
    insert_at(resolved, name, std::move(*d.get("v")), "defaults");
  };
  for (const Key& key : keys())
  {
    if (!applies(key, user))
      continue;
    auto star = key.name.find('*');
    if (star == std::string::npos)
    {
      add_default(key, key.name);
      continue;
    }
    std::string table = key.name.substr(0, star - 1);
    if (auto* t = user.at_path(table).as_table())
      for (auto&& [part, v] : *t)
        if (v.is_table())
        {
          // Tables with keys of their own (material.cornea) take no wildcards.
          const std::string prefix = table + "." + std::string(part.str()) + ".";
          bool declared = std::any_of(keys().begin(), keys().end(),
                                      [&](const Key& k)
                                      { return k.name.rfind(prefix, 0) == 0; });
          std::string name = key.name;
          name.replace(star, 1, std::string(part.str()));
          if (!declared)
            add_default(key, name);
        }
  }
  // Overlay user values (their nodes keep their source for later errors).
  std::function<void(const toml::table&, const std::string&)> overlay
      = [&](const toml::table& t, const std::string& prefix)
  {
    for (auto&& [k, v] : t)
    {
      std::string name = prefix.empty() ? std::string(k.str())
                                        : prefix + "." + std::string(k.str());
      const Key* key = find_key(name);
      if (v.is_table() && !(key && key->kind == Kind::options))
        overlay(*v.as_table(), name);
      else
      {
        toml::table holder;
        holder.insert("v", v);
        insert_at(resolved, name, std::move(*holder.get("v")), name);
      }
    }
  };
  overlay(user, "");

  return Scene(std::filesystem::absolute(file), std::move(user), std::move(resolved),
               std::move(notes));
}

const toml::node& Scene::node(const std::string& key) const
{
  const toml::node* n = _resolved.at_path(key).node();
  if (!n)
    throw std::logic_error("scene key '" + key + "' is not declared");
  return *n;
}

std::pair<std::string, int> Scene::origin(const std::string& key) const
{
  if (const toml::node* n = _user.at_path(key).node())
    return source_of(*n, _file.string());
  return {"", 0};
}

bool Scene::has(const std::string& key) const
{
  return _resolved.at_path(key).node() != nullptr;
}

namespace
{
/// A resolved value as the field type T holds it.
template <class T>
T value_as(const toml::node& n)
{
  T v{};
  Visitor::assign(n, &v);
  return v;
}
} // namespace

bool Scene::boolean(const std::string& key) const { return value_as<bool>(node(key)); }

int Scene::integer(const std::string& key) const { return value_as<int>(node(key)); }

double Scene::real(const std::string& key) const { return value_as<double>(node(key)); }

std::string Scene::string(const std::string& key) const
{
  return value_as<std::string>(node(key));
}

std::vector<std::string> Scene::strings(const std::string& key) const
{
  return value_as<std::vector<std::string>>(node(key));
}

std::vector<std::array<double, 3>> Scene::points(const std::string& key) const
{
  return value_as<Points>(node(key));
}

std::vector<std::pair<std::string, std::string>>
Scene::options(const std::string& key) const
{
  return value_as<Options>(node(key));
}

std::vector<std::string> Scene::tables(const std::string& key) const
{
  std::vector<std::string> out;
  if (const auto* t = _resolved.at_path(key).as_table())
    for (auto&& [k, v] : *t)
      if (v.is_table())
        out.emplace_back(k.str());
  return out;
}

std::filesystem::path Scene::path(const std::string& key) const
{
  std::filesystem::path p = string(key);
  return p.is_absolute() ? p : folder() / p;
}

std::string Scene::to_toml() const
{
  std::ostringstream s;
  s << "# Resolved scene: " << _file.string()
    << " with every default filled in.\n"
    << _resolved << "\n";
  return s.str();
}

std::string Scene::to_toml(const std::vector<std::string>& without) const
{
  toml::table t = _resolved;
  for (const auto& key : without)
  {
    const auto dot = key.find('.');
    if (auto* section = t[key.substr(0, dot)].as_table())
      section->erase(key.substr(dot + 1));
  }
  std::ostringstream s;
  s << t << "\n";
  return s.str();
}

std::string describe(bool markdown)
{
  std::ostringstream s;
  if (markdown)
    s << "| key | default | unit | accepted | description |\n"
      << "|---|---|---|---|---|\n";
  for (const Key& k : keys())
  {
    std::string acc = accepted(k);
    if (!k.unit.empty())
      acc = acc.substr(0, acc.rfind(" ["));
    const std::string when
        = k.when.empty() ? "" : " (only when " + k.when + ")";
    // A table cell escapes the column separator.
    auto escape_bars = [](const std::string& text)
    {
      std::string escaped;
      for (char c : text)
      {
        if (c == '|')
          escaped.push_back('\\');
        escaped.push_back(c);
      }
      return escaped;
    };
    if (markdown)
      s << "| `" << k.name << "` | `" << k.default_value << "` | "
        << (k.unit.empty() ? "-" : k.unit) << " | " << acc << " | "
        << escape_bars(k.description + when) << " |\n";
    else
      s << k.name << " = " << k.default_value
        << (k.unit.empty() ? "" : "  [" + k.unit + "]") << "\n    " << acc
        << ". " << k.description << when << "\n";
  }
  return s.str();
}

} // namespace nct::scene
