// Scene files: declared keys, validation and the resolved scene.
#pragma once

#include <array>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace nct::scene
{

/// A bad scene: the message names the file (or the --set option), the key
/// and what is accepted.
class Error : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// The kinds of value a key holds.
enum class Kind
{
  boolean,
  integer,
  real,
  choice,  ///< a string from a fixed list
  string,
  strings, ///< an array of strings
  points,  ///< an array of [x, y, z]
  options  ///< a free table of PETSc options (name = value)
};

/// One declared scene key.
struct Key
{
  std::string name; ///< dotted path; "*" stands for any table name
  Kind kind;
  std::string default_value; ///< TOML literal, e.g. "5", "0.05", "\"hgo\"", "[]"
  std::string unit;          ///< "" when dimensionless
  double min = -std::numeric_limits<double>::infinity(); ///< inclusive bounds
  double max = std::numeric_limits<double>::infinity();
  std::vector<std::string> choices;
  std::string description;
  /// "key=value[,key=value]": the key applies only when those choices are
  /// made (e.g. "mesh.source=eye"; "key=a|b" for either); setting it
  /// otherwise is a contradiction.
  std::string when = "";
};

/// Every key a scene may hold (cpp/scene/keys.cpp).
const std::vector<Key>& keys();

/// The documentation of every key: plain text, or a Markdown table.
std::string describe(bool markdown);

/// A validated scene: the file's values over the declared defaults.
class Scene
{
public:
  /// Read, override (`section.key=value`) and validate a scene file.
  /// Throws Error before any expensive work when anything is wrong.
  static Scene load(const std::filesystem::path& file,
                    const std::vector<std::string>& overrides = {});

  /// Does the resolved scene hold this key?
  bool has(const std::string& key) const;
  bool boolean(const std::string& key) const;
  int integer(const std::string& key) const;
  double real(const std::string& key) const;
  std::string string(const std::string& key) const;
  std::vector<std::string> strings(const std::string& key) const;
  std::vector<std::array<double, 3>> points(const std::string& key) const;
  /// PETSc options of an options table, as (name, value) pairs.
  std::vector<std::pair<std::string, std::string>>
  options(const std::string& key) const;
  /// Names of the sub-tables of a table, e.g. the parts under "material".
  std::vector<std::string> tables(const std::string& key) const;

  /// The scene file's folder: relative paths in the scene start there.
  std::filesystem::path folder() const { return _file.parent_path(); }
  std::filesystem::path file() const { return _file; }
  /// A path key resolved against the scene file's folder.
  std::filesystem::path path(const std::string& key) const;

  /// The resolved scene (every key with its value) as TOML.
  std::string to_toml() const;
  /// The resolved keys but `without` these ("section.key"), as TOML.
  std::string to_toml(const std::vector<std::string>& without) const;

private:
  Scene(std::filesystem::path file, toml::table resolved)
      : _file(std::move(file)), _resolved(std::move(resolved))
  {
  }
  const toml::node& node(const std::string& key) const;

  std::filesystem::path _file;
  toml::table _resolved;
};

/// Cross-checks of a resolved scene that no single key can make
/// (contradictory effects, missing files); throws Error.
void check_consistency(const Scene& scene);

} // namespace nct::scene
