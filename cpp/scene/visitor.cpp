#include "scene/visitor.h"

#include <sstream>

namespace nct::scene
{

void Visitor::string(const Entry& e, std::string& field)
{
  Key k = key(e, Kind::string);
  k.default_value = "\"" + e.default_value + "\"";
  entry(k, &field);
}

void Visitor::path(const Entry& e, std::filesystem::path& field)
{
  Key k = key(e, Kind::string);
  k.default_value = "\"" + e.default_value + "\"";
  std::string text = e.default_value;
  entry(k, &text);
  field = text.empty() ? std::filesystem::path() : resolve(text);
}

void Visitor::parse_default(const Key& key, Field field)
{
  const toml::table t = toml::parse("v = " + key.default_value);
  const toml::node& n = *t.get("v");
  auto number = [](const toml::node& x)
  { return x.is_integer() ? static_cast<double>(x.as_integer()->get()) : x.as_floating_point()->get(); };
  std::visit(
      [&](auto* f)
      {
        using T = std::remove_pointer_t<decltype(f)>;
        if constexpr (std::is_same_v<T, double>)
          *f = number(n);
        else if constexpr (std::is_same_v<T, int>)
          *f = static_cast<int>(n.as_integer()->get());
        else if constexpr (std::is_same_v<T, bool>)
          *f = n.as_boolean()->get();
        else if constexpr (std::is_same_v<T, std::string>)
          *f = n.as_string()->get();
        else if constexpr (std::is_same_v<T, std::vector<std::string>>)
        {
          f->clear();
          for (const auto& s : *n.as_array())
            f->push_back(s.as_string()->get());
        }
        else if constexpr (std::is_same_v<T, Points>)
        {
          f->clear();
          for (const auto& p : *n.as_array())
          {
            const auto& a = *p.as_array();
            f->push_back({number(a[0]), number(a[1]), number(a[2])});
          }
        }
        else
          f->clear(); // options: an empty table
      },
      field);
}

void Declarer::entry(const Key& key, Field) { keys.push_back(key); }

void Declarer::tables(const std::string&, const std::vector<std::string>& declared,
                      const std::function<void(const std::string&)>& each)
{
  for (const auto& part : declared)
    each(part);
}

Reader::Reader(const Scene& scene) : _scene(scene) {}

std::filesystem::path Reader::resolve(const std::string& text) const
{
  std::filesystem::path p = text;
  return p.is_absolute() ? p : _scene.folder() / p;
}

void Reader::entry(const Key& key, Field field)
{
  const std::string& name = key.name;
  if (!_scene.has(name))
  {
    parse_default(key, field);
    return;
  }
  std::visit(
      [&](auto* f)
      {
        using T = std::remove_pointer_t<decltype(f)>;
        if constexpr (std::is_same_v<T, double>)
          *f = _scene.real(name);
        else if constexpr (std::is_same_v<T, int>)
          *f = _scene.integer(name);
        else if constexpr (std::is_same_v<T, bool>)
          *f = _scene.boolean(name);
        else if constexpr (std::is_same_v<T, std::string>)
          *f = _scene.string(name);
        else if constexpr (std::is_same_v<T, std::vector<std::string>>)
          *f = _scene.strings(name);
        else if constexpr (std::is_same_v<T, Points>)
          *f = _scene.points(name);
        else
          *f = _scene.options(name);
      },
      field);
}

void Reader::tables(const std::string& section, const std::vector<std::string>&,
                    const std::function<void(const std::string&)>& each)
{
  for (const auto& part : _scene.tables(section))
    each(part);
}

} // namespace nct::scene
