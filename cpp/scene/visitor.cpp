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

void Visitor::assign(const toml::node& n, Field field)
{
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
        else if constexpr (std::is_same_v<T, std::vector<double>>)
        {
          f->clear();
          for (const auto& x : *n.as_array())
            f->push_back(number(x));
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
        else // options: name = value, the value as text
        {
          f->clear();
          for (auto&& [k, v] : *n.as_table())
          {
            std::ostringstream text;
            if (v.is_string())
              text << v.as_string()->get();
            else
              v.visit([&](auto&& x) { text << x; });
            f->emplace_back(std::string(k.str()), text.str());
          }
        }
      },
      field);
}

void Visitor::parse_default(const Key& key, Field field)
{
  const toml::table t = toml::parse("v = " + key.default_value);
  assign(*t.get("v"), field);
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
  if (const toml::node* n = _scene.find(key.name))
    assign(*n, field);
  else
    parse_default(key, field);
}

void Reader::tables(const std::string& section, const std::vector<std::string>&,
                    const std::function<void(const std::string&)>& each)
{
  for (const auto& part : _scene.tables(section))
    each(part);
}

} // namespace nct::scene
