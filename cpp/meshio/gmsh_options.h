// Scoped gmsh options.
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

} // namespace nct::meshio
