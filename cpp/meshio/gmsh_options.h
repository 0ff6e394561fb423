// Scoped gmsh options and temporary models.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <gmsh.h>

namespace nct::meshio
{

/// Sets gmsh numeric options, restoring the previous values on destruction.
class OptionGuard
{
public:
  OptionGuard() = default;
  OptionGuard(const OptionGuard&) = delete;
  OptionGuard& operator=(const OptionGuard&) = delete;
  ~OptionGuard()
  {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it)
      gmsh::option::setNumber(it->first, it->second);
  }

  void set(const std::string& name, double value)
  {
    double old = 0;
    gmsh::option::getNumber(name, old);
    saved_.emplace_back(name, old);
    gmsh::option::setNumber(name, value);
  }

private:
  std::vector<std::pair<std::string, double>> saved_;
};

/// A gmsh model made current for the span of a scope: on leaving, it and
/// the mesh size callback are removed (the previous model is not made
/// current again: the caller sets the one it wants).
class TemporaryModel
{
public:
  explicit TemporaryModel(std::string name) : _name(std::move(name)) { gmsh::model::add(_name); }
  TemporaryModel(const TemporaryModel&) = delete;
  TemporaryModel& operator=(const TemporaryModel&) = delete;
  ~TemporaryModel()
  {
    try
    {
      gmsh::model::setCurrent(_name);
      gmsh::model::mesh::removeSizeCallback();
      gmsh::model::remove();
    }
    catch (...) // gmsh 4.8 throws strings; never out of a destructor
    {
    }
  }

private:
  std::string _name;
};

} // namespace nct::meshio
