// A settings struct's entries, each a declared scene key bound to a field:
// one visit function per struct declares its keys (name, default, unit,
// range, description) and is run by a Declarer (the scene's key list, for
// validation and `nct describe`) or by a Reader (the scene's values into
// the fields).
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "scene/scene.h"

namespace nct::scene
{

/// A declared key but its kind and choices, which the visiting call gives:
/// {name, TOML default, unit, min, max, description, when}.
struct Entry
{
  std::string name;
  std::string default_value; ///< TOML literal ("5", "0.05", "[]"); bare for choice, string, path
  std::string unit;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::string description;
  std::string when = "";
};

/// (name, value) pairs of an options table.
using Options = std::vector<std::pair<std::string, std::string>>;
using Points = std::vector<std::array<double, 3>>;

/// Visits a settings struct's entries. `visit(Visitor&, S&)` functions call
/// one method per key, in the order `nct describe` lists them.
class Visitor
{
public:
  virtual ~Visitor() = default;
  void real(const Entry& e, double& field) { entry(key(e, Kind::real), &field); }
  void integer(const Entry& e, int& field) { entry(key(e, Kind::integer), &field); }
  void boolean(const Entry& e, bool& field) { entry(key(e, Kind::boolean), &field); }
  void string(const Entry& e, std::string& field);
  /// A file name, relative to the scene file's folder (empty: none).
  void path(const Entry& e, std::filesystem::path& field);
  void strings(const Entry& e, std::vector<std::string>& field)
  {
    entry(key(e, Kind::strings), &field);
  }
  /// An array of numbers, each in [e.min, e.max].
  void reals(const Entry& e, std::vector<double>& field) { entry(key(e, Kind::reals), &field); }
  void points(const Entry& e, Points& field) { entry(key(e, Kind::points), &field); }
  void options(const Entry& e, Options& field) { entry(key(e, Kind::options), &field); }
  /// A string from a fixed list, held as the value paired with it.
  template <class T>
  void choice(const Entry& e, T& field, const std::vector<std::pair<std::string, T>>& values)
  {
    Key k = key(e, Kind::choice);
    k.default_value = "\"" + e.default_value + "\"";
    for (const auto& [name, value] : values)
      k.choices.push_back(name);
    std::string text = e.default_value;
    entry(k, &text);
    for (const auto& [name, value] : values)
      if (name == text)
        field = value;
  }
  /// The tables of a section whose names the scene chooses (material.<part>):
  /// `each(part)` visits one. `declared`: the names declared with keys of
  /// their own ("*" for the rest).
  virtual void tables(const std::string& section, const std::vector<std::string>& declared,
                      const std::function<void(const std::string& part)>& each)
      = 0;

  /// A field of one of the kinds a key holds.
  using Field = std::variant<double*, int*, bool*, std::string*, std::vector<std::string>*,
                             std::vector<double>*, Points*, Options*>;
  /// Set `field` from a TOML value (of the field's kind, as validated).
  static void assign(const toml::node& value, Field field);

protected:
  /// One key and the field it sets (a choice's and a path's through a string).
  virtual void entry(const Key& key, Field field) = 0;
  /// Set `field` from a key's default (a TOML literal).
  static void parse_default(const Key& key, Field field);

private:
  /// A path as given, or resolved (a Reader: against the scene's folder).
  virtual std::filesystem::path resolve(const std::string& text) const { return text; }
  static Key key(const Entry& e, Kind kind)
  {
    return {e.name, kind, e.default_value, e.unit, e.min, e.max, {}, e.description, e.when};
  }
};

/// Collects the keys a visit declares.
class Declarer : public Visitor
{
public:
  std::vector<Key> keys;
  void tables(const std::string& section, const std::vector<std::string>& declared,
              const std::function<void(const std::string& part)>& each) override;

protected:
  void entry(const Key& key, Field field) override;
};

/// Reads a scene's values into the fields; a key that does not apply (its
/// `when` unmet) or whose value was refused keeps its default.
class Reader : public Visitor
{
public:
  explicit Reader(const Scene& scene);
  void tables(const std::string& section, const std::vector<std::string>& declared,
              const std::function<void(const std::string& part)>& each) override;

protected:
  void entry(const Key& key, Field field) override;
  std::filesystem::path resolve(const std::string& text) const override;

private:
  const Scene& _scene;
};

/// Sets every field to its declared default (no scene).
class Defaults : public Visitor
{
public:
  void tables(const std::string&, const std::vector<std::string>&,
              const std::function<void(const std::string&)>&) override
  {
  }

protected:
  void entry(const Key& key, Field field) override { parse_default(key, field); }
};

/// A settings struct with every entry at its declared default.
template <class S>
S defaults()
{
  S s{};
  Defaults d;
  visit(d, s);
  return s;
}

} // namespace nct::scene
