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

class Scene;

/// Every problem of an input file, reported at once: each names its place
/// (file:line, or the --set option), the key, the value and what is
/// accepted; they are sorted by line.
class Errors
{
public:
  /// `file`: the input file, which problems without a line name.
  explicit Errors(std::filesystem::path file) : _file(std::move(file)) {}
  /// A problem at `where` ("file:line", "--set key=value" or the file),
  /// `line` its line in the file (0: none).
  void add(const std::string& where, int line, const std::string& message);
  /// A problem with the file as a whole.
  void add(const std::string& message) { add(_file.string(), 0, message); }
  /// A problem with a key: placed where the scene set it (else the file).
  /// `message` names the key ("key 'x': ...").
  void at(const Scene& scene, const std::string& key, const std::string& message);
  /// A key whose value is refused (keeps its default; its conditions on
  /// other keys are not checked).
  void refuse(const std::string& key) { _refused.push_back(key); }
  bool refused(const std::string& key) const;
  const std::vector<std::string>& refused_keys() const { return _refused; }
  bool empty() const { return _problems.empty(); }
  std::size_t size() const { return _problems.size(); }
  /// Throw every problem as one Error (none: nothing).
  void raise() const;

private:
  struct Problem
  {
    int order; ///< the line; --set options after the lines, the file's last
    std::size_t seen;
    std::string text;
  };
  std::filesystem::path _file;
  std::vector<Problem> _problems;
  std::vector<std::string> _refused;
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
  reals,   ///< an array of numbers, each in the key's range
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

/// Every key a scene may hold, as the blocks' settings declare them
/// (cpp/settings/settings.cpp).
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
  /// The same, every problem into `errors` (a file that cannot be parsed
  /// throws at once): a refused value is left at its default.
  static Scene load(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                    Errors& errors);

  /// Where a key's value came from: "file:line" or the --set option,
  /// with its line (-1: a --set option); a default: ("", 0).
  std::pair<std::string, int> origin(const std::string& key) const;

  /// Does the resolved scene hold this key?
  bool has(const std::string& key) const;
  /// The resolved value of a key, or null where it does not apply.
  const toml::node* find(const std::string& key) const { return _resolved.at_path(key).node(); }
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

  /// What the reader did that the user should know: the file's keys that
  /// a --set option turned off, ignored ("file:line: key '...' ...").
  const std::vector<std::string>& notes() const { return _notes; }

  /// The resolved scene (every key with its value) as TOML.
  std::string to_toml() const;
  /// The resolved keys but `without` these ("section.key"), as TOML.
  std::string to_toml(const std::vector<std::string>& without) const;

private:
  Scene(std::filesystem::path file, toml::table user, toml::table resolved,
        std::vector<std::string> notes)
      : _file(std::move(file)), _user(std::move(user)), _resolved(std::move(resolved)),
        _notes(std::move(notes))
  {
  }
  const toml::node& node(const std::string& key) const;

  std::filesystem::path _file;
  toml::table _user; ///< the file's values and the --set ones, where they were given
  toml::table _resolved;
  std::vector<std::string> _notes;
};

} // namespace nct::scene
