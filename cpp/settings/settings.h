// Every block's settings: the scene's keys, each declared once (default,
// unit, range, description) in a visit function (cpp/settings/*.cpp),
// read once into typed structs and checked together before any meshing.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mpi.h>

#include "air/domain.h"
#include "biomarkers/biomarkers.h"
#include "air/problem.h"
#include "dynamics/time_step.h"
#include "eye/geometry.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "puff/load.h"
#include "scene/scene.h"
#include "scene/visitor.h"
#include "solid/material.h"
#include "solid/problem.h"
#include "solver/newton.h"
#include "zero_pressure/zero_pressure.h"

namespace nct
{

/// A file mesh opened in gmsh while the scene is checked, kept open until
/// the model meshes it: a file is opened once.
class OpenMesh
{
public:
  /// Throws std::runtime_error naming the file if gmsh cannot read it.
  OpenMesh(MPI_Comm comm, const std::filesystem::path& file,
           const std::map<std::string, double>& parameters);
  /// Its physical groups (every rank).
  const meshio::Groups& groups() const { return _groups; }
  /// Its tetrahedra and tagged triangles (meshio::extract), then gmsh is
  /// closed; once. Collective.
  meshio::Model extract(MPI_Comm comm, double size_max) const;

private:
  mutable std::unique_ptr<meshio::GmshSession> _gmsh; ///< null once extracted
  meshio::Groups _groups;
};

/// [mesh], [geometry], [boundary]: the model's meshes.
struct MeshSettings
{
  enum class Source
  {
    eye,
    file
  };
  Source source;
  section::Dimension dimension;              ///< 3D or a 2D section
  std::filesystem::path file;                ///< mesh.file, resolved
  double size_max;                           ///< [mm]
  scene::Options parameters;                 ///< a .geo's constants, as given
  eye::Refinement refinement;                ///< the idealised eye's
  eye::Geometry geometry;                    ///< the idealised eye's
  /// A file mesh's facet groups by condition (boundary.*).
  struct Boundaries
  {
    std::vector<std::string> fixed, symmetry, axis, cavity_wall, press, inlet, outlet, wall,
        interface, humor_open;
  } boundary;
  bool eye() const { return source == Source::eye; }
};

/// [support]: the fixed face clamped, or held by springs and dashpots
/// from the start of the dynamics (forms/support.py).
struct SupportSettings
{
  bool springs;
  double stiffness; ///< [N/mm]
  double damping;   ///< [N ms/mm]
};

/// [cavity], [inflate]: the humors, inflated to the IOP, then closed or
/// held at it.
struct CavitySettings
{
  bool closed;
  /// The humors' mass in the dynamics: none (massless), their translation
  /// (forms/humor_inertia.py), their flow (forms/humor_flow.py) or the
  /// full Navier-Stokes equations (forms/air_ale.py).
  enum class HumorInertia
  {
    none,
    translation,
    flow,
    navier_stokes
  };
  HumorInertia humor_inertia;
  /// Is the humor meshed (its flow, or Navier-Stokes)?
  bool meshed_humor() const
  {
    return humor_inertia == HumorInertia::flow || humor_inertia == HumorInertia::navier_stokes;
  }
  double humor_density;  ///< [g/mm^3]
  double humor_viscosity; ///< [MPa ms] (navier_stokes)
  /// A file mesh's humor: its volume groups (cavity.humor_inertia = "flow").
  std::vector<std::string> humor_groups;
  scene::Points origin; ///< a file mesh's volume origin [mm]
  double iop;           ///< [mmHg]
  int inflate_steps;
};

/// [zero_pressure]: the stress-free geometry behind the imaged eye.
struct ZeroPressureSettings
{
  bool enabled;
  zero_pressure::Settings fixed_point;
  bool reuse; ///< the inflate phase starts from the fixed point's last state
};

/// [press]: a follower pressure on the pressed surface, ramped.
struct PressSettings
{
  double pressure; ///< [mmHg]
  int steps;
  bool gaussian; ///< else uniform
  double width;  ///< [mm]
};

/// The solid block: discretisation, support, cavities, press, the rest,
/// the probes.
struct SolidSettings
{
  solid::Element element;
  SupportSettings support;
  CavitySettings cavity;
  ZeroPressureSettings zero_pressure;
  PressSettings press;
  double rest_duration; ///< [ms]
  scene::Points probes; ///< output.probes [mm]
};

/// [puff]: the device's puff (the prescribed load's or the inlet's shape
/// in time), its duration and the biomarkers' frames.
struct PuffSettings
{
  enum class Load
  {
    none,
    gaussian,
    pulse,
    table,
    air,
    fsi
  };
  Load load;
  double duration;       ///< [ms]
  double peak;           ///< [mmHg]
  double rise_rate;      ///< [mmHg/ms]
  double fall_rate;      ///< [mmHg/ms]
  double pulse_duration; ///< [ms]
  std::filesystem::path profile;
  double peak_time, width_t; ///< [ms]
  double width_r;            ///< [mm]
  std::filesystem::path table;
  double frame_rate;                 ///< [1/s]
  biomarkers::Definitions definitions; ///< the DCR parameters' unpublished choices
  /// The load is a pressure prescribed on the pressed surface.
  bool prescribed() const { return load == Load::gaussian || load == Load::pulse || load == Load::table; }
};

/// [inlet]: the air's inlet, the nozzle's bore on the eye or a file
/// mesh's inlet groups.
struct InletSettings
{
  enum class Profile
  {
    uniform,
    parabolic,
    table
  };
  double velocity; ///< [m/s]
  Profile profile;
  bool pulse; ///< the eye's history: sqrt of the measured pulse, else gaussian
  scene::Points direction, center, axes;
  std::filesystem::path table;
  bool circle; ///< the parabolic section (else a rectangle)
  double half_width_1, half_width_2, radius; ///< [mm]
  double ramp_time;                          ///< [ms]
};

/// [air]: the air block (puff.load = "air" or "fsi").
struct AirSettings
{
  bool rigid_eye; ///< air.eye: the eye a rigid wall (else none, the free jet)
  air::Fluid fluid;
  int bdf_order;
  double output_interval; ///< [ms]
  air::Domain domain;     ///< the nozzle's air about the eye
  InletSettings inlet;
  std::vector<std::string> force_on; ///< output.force_on
};

/// [fsi]: the coupling.
struct FsiSettings
{
  bool shape_derivative;
  bool fieldsplit; ///< the linear solver (else LU of the whole)
};

/// [solver]: Newton, the step control, the linear solver.
struct SolverSettings
{
  solver::NewtonSettings newton;
  int max_step_cuts;
  bool extrapolate; ///< the predictor (else the last state)
  bool ldlt;        ///< the solid's factorisation (else LU)
  scene::Options petsc;
};

/// [checkpoint].
struct CheckpointSettings
{
  int steps;
  double minutes;
  int keep;
};

/// [output].
struct OutputSettings
{
  bool fields;
};

/// Every block's settings.
struct Settings
{
  MeshSettings mesh;
  std::map<std::string, solid::Material> materials; ///< by part (volume group)
  SolidSettings solid;
  dynamics::TimeStep dynamics;
  dynamics::StepControl step_control; ///< [dynamics]'s choice of the steps
  PuffSettings puff;
  AirSettings air;
  mesh_motion::Settings mesh_motion;
  FsiSettings fsi;
  SolverSettings solver;
  CheckpointSettings checkpoint;
  OutputSettings output;

  /// The parts whose material is a fluid (a file mesh's).
  std::vector<std::string> fluid_parts() const;
};

/// What the check built beside the keys, for the model to take: the
/// idealised eye's shape, a file mesh opened in gmsh (a file is opened
/// once), the prescribed puff's pressure, the measured pulse's shape, a
/// file mesh's inlet table.
struct Built
{
  eye::Derived eye{};                              ///< the idealised eye's shape
  std::map<std::string, double> geo_constants;     ///< a .geo's constants (mesh.parameters)
  std::shared_ptr<OpenMesh> file_mesh;             ///< a file mesh, open
  std::shared_ptr<const puff::Load> puff_pressure; ///< the prescribed p(r, t) [mmHg]
  std::optional<puff::PulseShape> pulse;           ///< the measured pulse's shape, where used
  std::vector<std::array<double, 4>> inlet_table;  ///< a file mesh's inlet: x, y, z [mm], u [m/s]
};

/// A scene read once and checked: its resolved file, its settings and what
/// the check built.
struct Input
{
  scene::Scene scene;
  Settings settings;
  Built built;
};

/// Read a scene file (with --set overrides), its settings and check them
/// all, the files it names included (tables, a file mesh's groups),
/// without meshing. Throws scene::Error listing every problem. Collective.
Input read(MPI_Comm comm, const std::filesystem::path& file,
           const std::vector<std::string>& overrides = {});

void visit(scene::Visitor& v, Settings& s);
void visit(scene::Visitor& v, MeshSettings& s);
void visit(scene::Visitor& v, SolidSettings& s);
void visit(scene::Visitor& v, PuffSettings& s);
void visit(scene::Visitor& v, AirSettings& s);
void visit(scene::Visitor& v, InletSettings& s);
void visit(scene::Visitor& v, FsiSettings& s);
void visit(scene::Visitor& v, SolverSettings& s);
void visit(scene::Visitor& v, CheckpointSettings& s);
void visit(scene::Visitor& v, OutputSettings& s);

namespace eye
{
void visit(scene::Visitor& v, Geometry& g);
void visit(scene::Visitor& v, Refinement& r);
} // namespace eye
namespace air
{
void visit(scene::Visitor& v, Fluid& f);
void visit(scene::Visitor& v, Domain& d);
} // namespace air
namespace mesh_motion
{
void visit(scene::Visitor& v, Settings& s);
}
namespace dynamics
{
void visit(scene::Visitor& v, TimeStep& s);
void visit(scene::Visitor& v, StepControl& s);
}
namespace solid
{
/// [material.<part>]: `part`'s keys ("*": a file mesh's).
void visit(scene::Visitor& v, Material& m, const std::string& part);
}

} // namespace nct
