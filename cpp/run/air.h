// Running a scene whose puff is the air itself (puff.load = "air").
#pragma once

#include <mpi.h>
#include <nlohmann/json.hpp>

#include "io/output.h"
#include "scene/scene.h"

namespace nct
{

/// Distances from the nozzle's exit along the axis where the centreline
/// velocity is recorded [mm].
constexpr double centreline_distances[] = {2, 4, 6, 8, 10};

/// Mesh the air (about a rigid eye or alone) and march the air puff: the
/// inlet velocity follows the puff's Gaussian in time. Writes steps.csv,
/// centreline.csv, with the eye corneal_pressure.csv (the table
/// puff.load = "table" reads) and the XDMF velocity and pressure, and
/// returns the summary (also in summary.json).
nlohmann::json run_air(MPI_Comm comm, const scene::Scene& scene, io::RunFolder& folder);

} // namespace nct
