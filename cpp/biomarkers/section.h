// The corneal profiles of the horizontal section (docs/physics.md section 9):
// the displacement nodes of the anterior and posterior corneal surfaces
// on the plane z = 0, gathered on every rank.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <mpi.h>

#include "biomarkers/biomarkers.h"
#include "solid/problem.h"

namespace nct::biomarkers
{

/// One surface's nodes in the section, ordered by reference x >= 0.
struct SectionState
{
  std::vector<double> X;  ///< reference x [mm]
  std::vector<double> x;  ///< current x [mm]
  std::vector<double> y;  ///< current height along the axis [mm]
  std::vector<double> uy; ///< axial displacement [mm]
  std::vector<double> vx; ///< velocity across the section [mm/ms = m/s]
  std::vector<double> vy; ///< axial velocity [mm/ms = m/s]

  /// The full section (mirrored about the axis, quarter symmetry).
  Profile profile() const;
  /// Axial displacement at reference x = X0, linear between nodes.
  double displacement_at(double X0) const;
};

/// The nodes of a surface on z = 0, found once on the current reference
/// geometry (after any zero-pressure iteration) and sampled at each step.
class Section
{
public:
  /// The displacement nodes on the facets `facets` (local indices) with
  /// |z| below a tolerance; the axis is y. Throws if fewer than three
  /// nodes lie in the section or none on the axis.
  Section(const solid::Problem& problem, const std::vector<std::int32_t>& facets,
          const char* surface);
  /// The current state; collective, every rank gets all of it.
  SectionState sample() const;

private:
  MPI_Comm _comm;
  const solid::Problem& _problem;
  std::vector<std::int32_t> _nodes;      ///< owned block dofs in the section
  std::vector<double> _X;                ///< reference (x, y) of the gathered nodes
  std::vector<std::size_t> _order;       ///< gathered nodes sorted by reference x
};

} // namespace nct::biomarkers
