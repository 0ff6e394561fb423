// Reading the input files that drive many runs (studies, fits): TOML
// tables checked key by key, with errors naming the file and the key.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "scene/scene.h"

namespace nct::io
{

/// "file: key 'name': what"
scene::Error key_error(const std::filesystem::path& file, const std::string& key,
                       const std::string& what);

/// Every problem of a study or fit file: each check that may fail is
/// attempted, its error (a key_error) placed at the line of its key
/// ("factor[2].levels") in the file; the file's problems are raised at
/// once, sorted by line.
class KeyErrors
{
public:
  KeyErrors(const std::filesystem::path& file, const toml::table& table)
      : _file(file), _table(table), _errors(file)
  {
  }
  /// Run `check`; true if it threw no scene::Error (else the error is kept).
  template <class Check>
  bool attempt(Check&& check)
  {
    try
    {
      check();
      return true;
    }
    catch (const scene::Error& e)
    {
      add(e.what());
      return false;
    }
  }
  /// A problem's message ("file: key 'k': what", or any other), placed.
  void add(const std::string& message);
  bool empty() const { return _errors.empty(); }
  /// Throw every problem as one scene::Error (none: nothing).
  void raise() const { _errors.raise(); }

private:
  std::filesystem::path _file;
  const toml::table& _table;
  scene::Errors _errors;
  std::vector<std::string> _seen;
};

/// Parse a TOML file (a `what`, e.g. "study file"); throws scene::Error
/// naming the file, and the line and column of a syntax error.
toml::table parse_toml(const std::filesystem::path& file, const std::string& what);

/// The integer at `key` of the table `t` (named `section` in the file, e.g.
/// "study"), `def` if absent; a key_error unless in [lo, hi].
int integer(const toml::table& t, const std::string& section, const std::string& key, long def,
            long lo, long hi, const std::filesystem::path& file);

/// The TOML literal of a value node (what --set takes); numbers in their
/// shortest round trip (0.05, not 0.050000000000000003).
std::string literal(const toml::node& v);

/// The shortest TOML literal of a real number that reads back to it.
std::string literal(double x);

/// An array of strings, or (when `one_allowed`) one string taken as an
/// array of one.
std::vector<std::string> string_list(const toml::node& v, const std::filesystem::path& file,
                                     const std::string& key, bool one_allowed);

/// Refuse keys of `t` not in `known`: "unknown key; `table` takes ...",
/// each into `errors`. `where` prefixes the key in the message (e.g.
/// "factor[2].").
void refuse_unknown_keys(const toml::table& t, const std::set<std::string>& known,
                         const std::filesystem::path& file, const std::string& where,
                         const std::string& table, KeyErrors& errors);

/// A file named by a string at `key`, relative to `file`'s folder; it must
/// exist. `what` says what it is for the messages.
std::filesystem::path file_path(const std::filesystem::path& file, const std::string& key,
                                const toml::node* node, const std::string& what);

/// A name that labels a CSV column or row: letters, digits and _.+- only.
void check_name(const std::filesystem::path& file, const std::string& key,
                const std::string& name, const std::string& labels);

} // namespace nct::io
