// Running a scene: mesh, solve the load steps, write the run folder.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <mpi.h>
#include <nlohmann/json.hpp>

#include "run/model.h"
#include "settings/settings.h"

namespace nct
{

/// The solve could not go on: the message says which phase, at which load
/// and with which residual history. Output written so far stays valid.
class Diverged : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// PETSc, MPI and dolfinx's logging for the lifetime of the object. PETSc
/// does not see the command line: its options come from the scene and
/// from nct's --petsc.
class Runtime
{
public:
  explicit Runtime(const char* program);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;
};

/// The shared library that gives this process BLAS (the one MUMPS'
/// dgemm_ binds to), e.g. OpenBLAS through Debian's libblas.so.3
/// alternative; "none" if no BLAS is loaded.
std::string blas_library();

/// Command-line settings of a run.
struct RunOptions
{
  std::filesystem::path out;  ///< run folder
  std::vector<std::pair<std::string, std::string>> petsc; ///< overrides the scene's
  /// Continue the run in `out` from its last checkpoint (out/checkpoint).
  bool resume = false;
};

/// Run a scene into a run folder and return its summary (also written to
/// out/summary.json). Phases: the zero-pressure geometry (if enabled),
/// inflation by a pressure ramp, closing the cavities (cavity.model =
/// "closed"), a surface pressure ramp (press.pressure != 0), then in
/// dynamics a rest with the loads held (rest.duration > 0) and the air
/// puff (puff.load), whose frames give the Corvis biomarkers.
nlohmann::json run(MPI_Comm comm, const Input& input, const RunOptions& options);

} // namespace nct
