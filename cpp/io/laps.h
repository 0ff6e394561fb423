// Wall-time laps into named totals: where an assembly's time goes.
#pragma once

#include <map>
#include <string>

#include <mpi.h>

namespace nct::io
{

/// Each call adds the wall time since the last call (or since the laps
/// began) to `part`'s total [s].
class Laps
{
public:
  explicit Laps(std::map<std::string, double>& totals) : _totals(totals), _t(MPI_Wtime()) {}
  void operator()(const char* part)
  {
    const double now = MPI_Wtime();
    _totals[part] += now - _t;
    _t = now;
  }

private:
  std::map<std::string, double>& _totals;
  double _t;
};

} // namespace nct::io
