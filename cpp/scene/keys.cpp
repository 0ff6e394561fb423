// Every scene key, declared once: default, unit, accepted range, description.
#include "scene/scene.h"

#include <set>
#include <tuple>

namespace nct::scene
{
namespace
{

using K = Kind;
constexpr double inf = std::numeric_limits<double>::infinity();

/// The keys of one material table. Defaults are those of `part`.
struct MaterialDefaults
{
  std::string model;
  std::string c10, k1, k2, kappa, youngs_modulus, poisson_ratio;
};

void add_material(std::vector<Key>& keys, const std::string& part,
                  const MaterialDefaults& d, bool fibres_from_geometry,
                  const std::string& when)
{
  const std::size_t first = keys.size();
  const std::string m = "material." + part + ".";
  keys.push_back({m + "model", K::choice, "\"" + d.model + "\"", "", -inf, inf,
                  {"hgo", "neo_hookean", "compressible_neo_hookean", "saint_venant_kirchhoff",
                   "fluid"},
                  "material law of the part: hgo, neo_hookean (nearly incompressible, C10 "
                  "and kappa), compressible_neo_hookean (E and nu: Hooke's law at small "
                  "strain, stable in compression), saint_venant_kirchhoff (E and nu: linear "
                  "in the Green-Lagrange strain, softens and collapses in compression), or "
                  "fluid (file meshes with puff.load = \"fsi\": the part is incompressible "
                  "Newtonian fluid, the air block's Navier-Stokes)"});
  keys.push_back({m + "c10", K::real, d.c10, "MPa", 1e-6, 1e5, {},
                  "matrix stiffness C10 (hgo, neo_hookean); shear modulus 2 C10"});
  keys.push_back({m + "k1", K::real, d.k1, "MPa", 0, 1e3, {},
                  "fibre stiffness k1 (hgo); 0 makes the part isotropic"});
  keys.push_back({m + "k2", K::real, d.k2, "", 1e-3, 1e4, {},
                  "fibre nonlinearity k2 (hgo)"});
  keys.push_back({m + "kappa", K::real, d.kappa, "MPa", 1e-3, 1e7, {},
                  "bulk modulus of the volumetric penalty (hgo, neo_hookean)"});
  keys.push_back({m + "youngs_modulus", K::real, d.youngs_modulus, "MPa", 1e-9,
                  1e5, {}, "Young's modulus E (compressible_neo_hookean, saint_venant_kirchhoff)"});
  keys.push_back({m + "poisson_ratio", K::real, d.poisson_ratio, "", 0, 0.499, {},
                  "Poisson's ratio nu (compressible_neo_hookean, saint_venant_kirchhoff); "
                  "bulk modulus E / (3 (1 - 2 nu))"});
  keys.push_back({m + "density", K::real, "0.0011", "g/mm^3", 1e-9, 1e3, {},
                  "mass density (dynamic phases; a fluid's density)"});
  if (!fibres_from_geometry)
    keys.push_back({m + "viscosity", K::real, "1.8e-8", "MPa ms", 1e-12, 1e3, {},
                    "dynamic viscosity (fluid)"});
  if (!fibres_from_geometry)
    keys.push_back({m + "fibre_directions", K::points, "[]", "", -inf, inf, {},
                    "up to two constant fibre directions (hgo), normalised on "
                    "use; none makes the part isotropic"});
  for (std::size_t i = first; i < keys.size(); ++i)
    keys[i].when = when;
}

/// Mark the keys from `first` on as applying only when `when` holds
/// (those with a narrower condition of their own keep it).
void only_when(std::vector<Key>& keys, std::size_t first, const std::string& when)
{
  for (std::size_t i = first; i < keys.size(); ++i)
    if (keys[i].when.empty())
      keys[i].when = when;
}

std::vector<Key> declare()
{
  std::vector<Key> k;
  // mesh
  k.push_back({"mesh.source", K::choice, "\"eye\"", "", -inf, inf, {"eye", "file"},
               "the parametric idealised eye, or an external gmsh mesh (mesh.file)"});
  k.push_back({"mesh.file", K::string, "\"\"", "", -inf, inf, {},
               "external mesh (.msh, or a .geo that gmsh meshes), relative to the "
               "scene file; its physical groups map to materials and boundaries"});
  k.push_back({"mesh.size_max", K::real, "0.0", "mm", 0, 1e3, {},
               "file: largest element when nct meshes a .geo (0: as the .geo says)"});
  k.push_back({"mesh.parameters", K::options, "{}", "", -inf, inf, {},
               "file: numbers for a .geo's constants, name = value, each declared there "
               "as DefineConstant[name = {default, Name \"Parameters/name\"}] (e.g. its "
               "element sizes)"});
  only_when(k, k.size() - 3, "mesh.source=file");
  std::size_t eye_keys = k.size();
  k.push_back({"mesh.layers", K::integer, "5", "", 1, 12, {},
               "eye: elements through the wall thickness"});
  k.push_back({"mesh.size_cornea", K::real, "0.5", "mm", 0.05, 5, {},
               "eye: in-plane element size in the cornea"});
  k.push_back({"mesh.size_limbus", K::real, "0.5", "mm", 0.05, 5, {},
               "eye: in-plane element size in the limbus"});
  k.push_back({"mesh.size_sclera", K::real, "1.5", "mm", 0.05, 10, {},
               "eye: in-plane element size in the sclera"});
  k.push_back({"mesh.size_lens", K::real, "0.8", "mm", 0.05, 5, {},
               "eye: in-plane element size in the lens and zonule"});
  k.back().when = "mesh.source=eye,geometry.internal_structures=true";
  // geometry of the idealised eye
  k.push_back({"geometry.cornea_anterior_radius", K::real, "7.8", "mm", 5, 12, {},
               "radius of the anterior corneal sphere"});
  k.push_back({"geometry.cornea_posterior_radius", K::real, "6.5", "mm", 4, 12, {},
               "radius of the posterior corneal sphere"});
  k.push_back({"geometry.cornea_central_thickness", K::real, "0.55", "mm", 0.2, 1.5,
               {}, "central corneal thickness"});
  k.push_back({"geometry.limbus_diameter", K::real, "11.7", "mm", 8, 14, {},
               "diameter of the anterior cornea-sclera junction"});
  k.push_back({"geometry.limbus_width", K::real, "1.0", "mm", 0.2, 4, {},
               "meridional width of the limbus band, centred on the junction"});
  k.push_back({"geometry.sclera_outer_radius", K::real, "12.0", "mm", 9, 15, {},
               "outer radius of the scleral sphere (centred at the origin)"});
  k.push_back({"geometry.sclera_thickness", K::real, "0.8", "mm", 0.3, 2, {},
               "scleral thickness"});
  k.push_back({"geometry.cut_y", K::real, "-4.0", "mm", -11, 8, {},
               "posterior cut plane y = cut_y (fixed); the cavity is closed there"});
  k.push_back({"geometry.internal_structures", K::boolean, "false", "", -inf, inf, {},
               "lens (cortex, nucleus), ciliary zonule and vitreous membrane; they split "
               "the cavity into aqueous and vitreous"});
  only_when(k, eye_keys, "mesh.source=eye");
  const std::size_t internal_keys = k.size();
  k.push_back({"geometry.anterior_chamber_depth", K::real, "3.0", "mm", 1, 6, {},
               "posterior corneal apex to the anterior lens pole"});
  k.push_back({"geometry.lens_thickness", K::real, "4.0", "mm", 2, 6, {},
               "lens thickness on the axis"});
  k.push_back({"geometry.lens_diameter", K::real, "9.5", "mm", 6, 11, {},
               "lens diameter at its equator"});
  k.push_back({"geometry.lens_anterior_radius", K::real, "10.0", "mm", 5, 20, {},
               "radius of the anterior lens surface"});
  k.push_back({"geometry.lens_posterior_radius", K::real, "6.0", "mm", 4, 20, {},
               "radius of the posterior lens surface"});
  k.push_back({"geometry.lens_nucleus_fraction", K::real, "0.6", "", 0.1, 0.9, {},
               "the nucleus spans this fraction of the lens radius (and the middle layers)"});
  k.push_back({"geometry.ciliary_offset", K::real, "2.0", "mm", 0.2, 6, {},
               "arc length on the inner sclera from the posterior cornea-sclera junction "
               "back to the zonule's attachment ring"});
  only_when(k, internal_keys, "mesh.source=eye,geometry.internal_structures=true");
  // materials
  const std::string eye = "mesh.source=eye";
  const std::string internal = "mesh.source=eye,geometry.internal_structures=true";
  add_material(k, "cornea", {"hgo", "0.05", "0.010", "100", "5.0", "1.0", "0.3"}, true, eye);
  add_material(k, "limbus", {"hgo", "0.05", "0.010", "100", "5.0", "1.0", "0.3"}, true, eye);
  add_material(k, "sclera", {"neo_hookean", "0.8", "0", "1", "80.0", "1.0", "0.3"}, true, eye);
  // Internal structures: E from design.md section 5, "linear elastic" there
  // taken as the compressible neo-Hookean (Hooke's law at small strain,
  // stable in compression). The lens is nearly incompressible: nu = 0.49,
  // as in the lens models since Fisher (J Physiol 212 (1971) 147) and
  // Burd et al. (Vision Res 42 (2002) 2235); it keeps the soft nucleus'
  // bulk modulus (5 kPa, 37 mmHg) above the IOP. The thin zonule and
  // membrane keep 0.45 (their volume change does not matter).
  for (auto [part, E, nu] : {std::tuple{"lens_cortex", "0.35", "0.49"},
                             {"lens_nucleus", "0.0003", "0.49"},
                             {"zonule", "0.35", "0.45"},
                             {"vitreous_membrane", "0.35", "0.45"}})
    add_material(k, part, {"compressible_neo_hookean", "0.05", "0", "1", "5.0", E, nu}, true,
                 internal);
  add_material(k, "*", {"neo_hookean", "0.5", "0", "1", "50.0", "1.0", "0.3"}, false,
               "mesh.source=file");
  // discretisation
  k.push_back({"fem.degree", K::integer, "2", "", 1, 2, {},
               "polynomial degree of the displacement (Lagrange)"});
  k.push_back({"fem.quadrature", K::choice, "\"reduced\"", "", -inf, inf,
               {"reduced", "full"},
               "cell quadrature: reduced = degree 2(p-1), at least 1 (the 1- and 4-point "
               "rules of the standard linear and quadratic tetrahedra, exact for linear "
               "elasticity); full = degree 2p, about 3x dearer assembly at p = 2"});
  k.push_back({"fem.formulation", K::choice, "\"displacement\"", "", -inf, inf,
               {"displacement", "mixed"},
               "displacement = u only: the volumetric energy kappa/2 (ln J)^2 at every "
               "quadrature point (locks as kappa/mu grows); mixed = displacement-pressure "
               "P2/P0, the pressure constant per cell and condensed out (the volumetric "
               "energy at the centroid): no locking; needs fem.degree = 2"});
  // boundaries of an external mesh (the eye's are built in)
  std::size_t file_keys = k.size();
  k.push_back({"boundary.fixed", K::strings, "[]", "", -inf, inf, {},
               "file: facet groups clamped (u = 0)"});
  k.push_back({"boundary.symmetry", K::strings, "[]", "", -inf, inf, {},
               "file: facet groups on axis-aligned symmetry planes (u . n = 0; in the "
               "fluid: slip, and the mesh slides along them)"});
  k.push_back({"boundary.cavity_wall", K::strings, "[]", "", -inf, inf, {},
               "file: facet groups bounding the fluid cavity (IOP acts here)"});
  k.push_back({"boundary.surface_load", K::strings, "[]", "", -inf, inf, {},
               "file: facet groups loaded by press.pressure"});
  k.push_back({"boundary.inlet", K::strings, "[]", "", -inf, inf, {},
               "file, fsi: fluid facet groups where the velocity is inlet.* (a profile "
               "across the section times a ramp in time)"});
  k.push_back({"boundary.outlet", K::strings, "[]", "", -inf, inf, {},
               "file, fsi: fluid facet groups with the natural outflow condition sigma n "
               "= 0 and backflow stabilisation (air.backflow)"});
  k.push_back({"boundary.wall", K::strings, "[]", "", -inf, inf, {},
               "file, fsi: fluid facet groups of rigid no-slip walls (u = 0); the fluid's "
               "force on them is its consistent reaction"});
  k.push_back({"boundary.interface", K::strings, "[]", "", -inf, inf, {},
               "file, fsi: the fluid-solid interface's facet groups; none: the faces "
               "between fluid and solid cells, found from the volume groups (the group "
               "'interface')"});
  k.push_back({"cavity.origin", K::points, "[[0.0, 0.0, 0.0]]", "mm", -inf, inf, {},
               "file: point on every symmetry plane and on any flat closing cap; "
               "the cavity volume is taken about it"});
  only_when(k, file_keys, "mesh.source=file");
  // the support of the fixed face (the eye's cut, a file's boundary.fixed)
  k.push_back({"support.model", K::choice, "\"clamped\"", "", -inf, inf,
               {"clamped", "springs"},
               "clamped = u = 0 throughout; springs = clamped in the quasi-static phases, "
               "then from the start of the dynamics held by springs and dashpots "
               "(forms/support.py) that take over the clamp's reaction: the whole eye "
               "moves in the orbit"});
  const std::size_t support_keys = k.size();
  k.push_back({"support.stiffness", K::real, "0.35", "N/mm", 1e-9, 1e6, {},
               "the whole model's spring stiffness, spread evenly over the fixed face "
               "(Kling et al. 2014, table 3: 350 N/m for the human eye)"});
  k.push_back({"support.damping", K::real, "100.0", "N ms/mm", 0, 1e6, {},
               "the whole model's dashpot, spread evenly over the fixed face (Kling et "
               "al. 2014, table 3: 100 kg/s = 100 N ms/mm)"});
  only_when(k, support_keys, "support.model=springs");
  // the fluid cavities (humors)
  k.push_back({"cavity.model", K::choice, "\"closed\"", "", -inf, inf,
               {"closed", "constant_pressure"},
               "after inflation: closed = each cavity keeps its volume and its pressure "
               "is an unknown (incompressible humor); constant_pressure = the pressure "
               "stays at the IOP (open system)"});
  // phase: zero-pressure geometry
  k.push_back({"zero_pressure.enabled", K::boolean, "false", "", -inf, inf, {},
               "take the mesh as the eye imaged at inflate.iop and first find its "
               "stress-free geometry (backward-displacement fixed point)"});
  const std::size_t zero_pressure_keys = k.size();
  k.push_back({"zero_pressure.tolerance", K::real, "1e-4", "mm", 1e-10, 1, {},
               "stop when no node of the pressurised stress-free geometry is farther "
               "than this from the imaged one"});
  k.push_back({"zero_pressure.max_iterations", K::integer, "30", "", 1, 500, {},
               "fixed-point iterations before the run stops"});
  k.push_back({"zero_pressure.acceleration", K::choice, "\"aitken\"", "", -inf, inf,
               {"aitken", "none"},
               "aitken = dynamic relaxation of each update (Irons-Tuck); none = the "
               "plain fixed point X -= x(X) - x_imaged"});
  k.push_back({"zero_pressure.round_trip", K::choice, "\"reuse\"", "", -inf, inf,
               {"reuse", "ramp"},
               "the inflate phase after zero pressure: reuse = one step from the fixed "
               "point's last pressurised state (the inflated stress-free geometry); ramp "
               "= inflate the stress-free geometry again from rest in inflate.steps, an "
               "independent round trip at the ramp's cost"});
  only_when(k, zero_pressure_keys, "zero_pressure.enabled=true");
  // phase: inflation
  k.push_back({"inflate.iop", K::real, "15.0", "mmHg", 0, 200, {},
               "intraocular pressure reached at the end of the inflation ramp"});
  k.push_back({"inflate.steps", K::integer, "5", "", 1, 10000, {},
               "load steps of the linear pressure ramp from zero"});
  // phase: press (a static surface pressure, after inflation and closing)
  k.push_back({"press.pressure", K::real, "0.0", "mmHg", -1e6, 1e6, {},
               "peak follower pressure on the loaded surface (the eye: the anterior "
               "cornea; a file mesh: boundary.surface_load); negative pulls; 0 skips "
               "the phase"});
  k.push_back({"press.steps", K::integer, "5", "", 1, 10000, {},
               "load steps of the linear ramp from zero"});
  k.push_back({"press.profile", K::choice, "\"uniform\"", "", -inf, inf,
               {"uniform", "gaussian"},
               "shape across the surface: uniform, or gaussian in the distance r from "
               "the y axis, exp(-r^2 / (2 width^2))"});
  k.push_back({"press.width", K::real, "1.5", "mm", 1e-3, 1e3, {},
               "standard deviation of the gaussian profile", "press.profile=gaussian"});
  // dynamic phases: the time integrator (forms/dynamics.py)
  k.push_back({"dynamics.dt", K::real, "0.1", "ms", 1e-4, 1e5, {},
               "time step of the rest and puff phases (halved when Newton fails, down to "
               "2^-solver.max_step_cuts of it)"});
  k.push_back({"dynamics.rho_inf", K::real, "0.8", "", 0, 1, {},
               "generalised-alpha spectral radius at infinite frequency: 1 keeps every "
               "mode (no numerical dissipation), 0 damps the unresolved ones in one step"});
  k.push_back({"dynamics.damping", K::real, "0.1", "1/ms", 0, 1e3, {},
               "mass-proportional (Rayleigh) damping coefficient"});
  // phase: rest (dynamic, loads held)
  k.push_back({"rest.duration", K::real, "0.0", "ms", 0, 1e3, {},
               "time the closed, inflated eye is followed before the puff with the loads "
               "held (it should not move); 0 skips the phase"});
  // phase: the air puff as a prescribed pressure p(r, t) on the anterior cornea
  k.push_back({"puff.load", K::choice, "\"none\"", "", -inf, inf,
               {"none", "gaussian", "pulse", "table", "air", "fsi"},
               "none skips the phase; gaussian = peak exp(-(t - peak_time)^2 / (2 "
               "width_t^2)) exp(-r^2 / (2 width_r^2)); pulse = peak s(t) f(r), s the "
               "measured pulse's shape (rise_rate, fall_rate, pulse_duration) and f the "
               "radial profile of a CFD run (profile); table = a CSV file (t_ms, r_mm, "
               "p_mmHg) such as a CFD run writes; air = the air itself, computed from the "
               "nozzle (air.*) on a rigid eye or on none, writing such a table; fsi = the "
               "air and the eye two-way coupled in one Newton system (air.*, mesh_motion.*, "
               "fsi.*)"});
  const std::size_t puff_keys = k.size();
  k.push_back({"puff.duration", K::real, "20.0", "ms", 1e-3, 1e7, {},
               "time followed from the start of the puff", "puff.load=gaussian|pulse|table|air|fsi"});
  k.push_back({"puff.peak", K::real, "65.0", "mmHg", -1e4, 1e4, {},
               "peak air pressure at the apex (with air.inlet_history = \"pulse\": the "
               "target the pulse's edges are relative to)", "puff.load=gaussian|pulse|air|fsi"});
  k.push_back({"puff.rise_rate", K::real, "8.94", "mmHg/ms", 1e-3, 1e5, {},
               "the pulse's mean rate of rise: the peak over the rising edge's length "
               "(a raised cosine, cpp/puff/load.h)", "puff.load=pulse|air|fsi"});
  k.push_back({"puff.fall_rate", K::real, "11.18", "mmHg/ms", 1e-3, 1e5, {},
               "the mean rate of fall (magnitude): the peak over the falling edge's length",
               "puff.load=pulse|air|fsi"});
  k.push_back({"puff.pulse_duration", K::real, "21.48", "ms", 1e-3, 1e4, {},
               "the pulse's length from onset (t = 0) to end; what the edges leave of it "
               "is a hold at the peak (must not be negative)", "puff.load=pulse|air|fsi"});
  k.push_back({"puff.profile", K::string, "\"\"", "", -inf, inf, {},
               "CSV file with the header r_mm,p_mmHg from r = 0 (e.g. a CFD run's "
               "corneal pressure at its peak), relative to the scene file; the pulse is "
               "scaled by p(r) / p(0)", "puff.load=pulse"});
  k.push_back({"puff.peak_time", K::real, "10.0", "ms", 0, 1e3, {},
               "time of the peak from the start of the puff", "puff.load=gaussian|air|fsi"});
  k.push_back({"puff.width_t", K::real, "3.0", "ms", 1e-3, 1e3, {},
               "standard deviation in time", "puff.load=gaussian|air|fsi"});
  k.push_back({"puff.width_r", K::real, "1.5", "mm", 1e-3, 1e3, {},
               "standard deviation in the distance r from the eye's axis",
               "puff.load=gaussian"});
  k.push_back({"puff.table", K::string, "\"\"", "", -inf, inf, {},
               "CSV file with the header t_ms,r_mm,p_mmHg, relative to the scene file "
               "(zero before its first and after its last time)", "puff.load=table"});
  k.push_back({"puff.frame_rate", K::real, "4330.0", "1/s", 100, 1e5, {},
               "rate at which the corneal profiles are sampled (Corvis ST: 4330 frames/s)"});
  k.push_back({"puff.apex_window", K::real, "1.0", "mm", 0.05, 5, {},
               "applanation: the apex curvature is fitted over |x| <= this"});
  k.push_back({"puff.radius_window", K::real, "1.5", "mm", 0.1, 5, {},
               "the HC radius and the inverse concave radius are fitted over |x| <= this"});
  k.push_back({"puff.flatness", K::real, "0.02", "mm", 1e-6, 1, {},
               "applanation length: the profile is flat where it stays within this of "
               "its height on the axis"});
  only_when(k, puff_keys, "puff.load=gaussian|pulse|table|fsi");
  // the air (puff.load = "air" or "fsi"): stabilised ALE Navier-Stokes,
  // forms/air.py and forms/air_ale.py
  const std::size_t air_keys = k.size();
  k.push_back({"air.eye", K::choice, "\"rigid\"", "", -inf, inf, {"rigid", "none"},
               "rigid = the idealised eye (geometry.*, mesh.*) is a fixed no-slip wall in the "
               "air; none = the free jet, the eye's place left to the air",
               "mesh.source=eye,puff.load=air"});
  k.push_back({"air.density", K::real, "1.25e-6", "g/mm^3", 1e-9, 1e-2, {},
               "air density"});
  k.push_back({"air.viscosity", K::real, "1.8e-8", "MPa ms", 1e-12, 1, {},
               "air dynamic viscosity"});
  k.push_back({"air.inlet_velocity", K::real, "120.0", "m/s", 0, 1e3, {},
               "air speed on the nozzle's axis at the inlet at the puff's peak"});
  k.push_back({"air.inlet_history", K::choice, "\"gaussian\"", "", -inf, inf,
               {"gaussian", "pulse"},
               "the inlet speed in time: gaussian = inlet_velocity exp(-(t - "
               "puff.peak_time)^2 / (2 puff.width_t^2)); pulse = inlet_velocity sqrt(s(t)), "
               "s the measured pulse's shape (puff.peak, rise_rate, fall_rate, "
               "pulse_duration): the quasi-steady jet's stagnation pressure follows s"});
  k.push_back({"air.inlet_profile", K::choice, "\"plug\"", "", -inf, inf,
               {"plug", "parabolic"},
               "shape across the nozzle's bore: plug = uniform, parabolic = 1 - (r / "
               "bore radius)^2 (half the flow rate)"});
  only_when(k, air_keys, "mesh.source=eye,puff.load=air|fsi"); // the nozzle's air; a file mesh's fluid: material.*
  const std::size_t air_numerics = k.size();
  k.push_back({"air.backflow", K::real, "1.0", "", 0, 10, {},
               "outlet backflow stabilisation beta (>= 0.5 is energy stable; 0 turns it off)"});
  k.push_back({"air.stabilisation_time", K::real, "0.25", "ms", 1e-4, 1e3, {},
               "time scale T of the stabilisation parameter tau_M = (4/T^2 + a.G a + ...)^-1/2: "
               "fixed, not the time step, so that the time steps converge to one solution; it "
               "bounds tau where the air is still (forms/navier_stokes.py)"});
  k.push_back({"air.dt", K::real, "0.25", "ms", 1e-5, 1e5, {},
               "time step (halved when Newton fails, down to 2^-solver.max_step_cuts of it); "
               "the coupled puff steps by dynamics.dt", "puff.load=air"});
  k.push_back({"air.bdf_order", K::integer, "2", "", 1, 2, {},
               "order of the backward differentiation formula in time (the first step: 1)"});
  k.push_back({"air.output_interval", K::real, "1.0", "ms", 1e-5, 1e5, {},
               "time between the XDMF velocity and pressure fields (output.fields)"});
  only_when(k, air_numerics, "puff.load=air|fsi");
  const std::size_t nozzle_keys = k.size();
  k.push_back({"air.radius", K::real, "50.0", "mm", 5, 500, {},
               "radius of the air domain about the optical axis"});
  k.push_back({"air.nozzle_diameter", K::real, "2.4", "mm", 0.1, 20, {},
               "inner diameter of the nozzle (its bore)"});
  k.push_back({"air.nozzle_outer_diameter", K::real, "6.0", "mm", 0.2, 100, {},
               "outer diameter of the nozzle's tube"});
  k.push_back({"air.nozzle_distance", K::real, "11.0", "mm", 1, 100, {},
               "distance from the nozzle's exit to the corneal apex, along the axis"});
  k.push_back({"air.nozzle_length", K::real, "2.0", "mm", 0.5, 200, {},
               "length of the bore from the inlet (the device's face) to the exit"});
  k.push_back({"air.size_nozzle", K::real, "0.1", "mm", 0.02, 10, {},
               "element size in the nozzle's bore and one bore radius beyond its exit"});
  k.push_back({"air.size_jet", K::real, "0.15", "mm", 0.02, 10, {},
               "element size within air.jet_radius of the axis, from the inlet to the eye"});
  k.push_back({"air.jet_radius", K::real, "2.0", "mm", 0.1, 50, {},
               "radius of the finely meshed core about the axis"});
  k.push_back({"air.size_far", K::real, "5.0", "mm", 0.05, 100, {},
               "largest element size (sizes grow 0.25 mm per mm away from the core)"});
  only_when(k, nozzle_keys, "mesh.source=eye,puff.load=air|fsi");
  // the inlet of a file mesh's fluid (puff.load = "fsi"), cpp/air/inlet
  const std::size_t inlet_keys = k.size();
  k.push_back({"inlet.velocity", K::real, "1.0", "m/s", 0, 1e3, {},
               "the profile's largest speed (on its axis or centre line) once ramped",
               "inlet.profile=uniform|parabolic"});
  k.push_back({"inlet.direction", K::points, "[]", "", -inf, inf, {},
               "the flow's direction at the inlet; none: the inlet's inward normal (a "
               "plane inlet)"});
  k.push_back({"inlet.profile", K::choice, "\"uniform\"", "", -inf, inf,
               {"uniform", "parabolic", "table"},
               "uniform across the inlet; parabolic over inlet.section: a rectangle "
               "prod_i (1 - (s_i / a_i)^2) (s_i along inlet.axes from inlet.center, a_i "
               "= inlet.half_width_i; inf: no variation that way, a channel or a slab) or "
               "a circle 1 - (r / inlet.radius)^2; table: speeds at points (inlet.table), "
               "between them their inverse distance weighted mean (Shepard, power 2)"});
  k.push_back({"inlet.table", K::string, "\"\"", "", -inf, inf, {},
               "CSV file with the header x_mm,y_mm,z_mm,u_m_s (the speed along "
               "inlet.direction once ramped), relative to the scene file",
               "inlet.profile=table"});
  k.push_back({"inlet.section", K::choice, "\"rectangle\"", "", -inf, inf,
               {"rectangle", "circle"}, "the parabolic profile's section",
               "inlet.profile=parabolic"});
  k.push_back({"inlet.center", K::points, "[[0.0, 0.0, 0.0]]", "mm", -inf, inf, {},
               "the section's centre (on the inlet)", "inlet.profile=parabolic"});
  k.push_back({"inlet.axes", K::points, "[[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]", "", -inf, inf,
               {}, "two directions across the rectangle (normalised on use)",
               "inlet.profile=parabolic,inlet.section=rectangle"});
  for (const char* axis : {"1", "2"})
    k.push_back({std::string("inlet.half_width_") + axis, K::real, "inf", "mm", 1e-9, inf, {},
                 std::string("the rectangle's half width along the inlet.axes' vector ") + axis
                     + " (inf: unbounded, no variation that way)",
                 "inlet.profile=parabolic,inlet.section=rectangle"});
  k.push_back({"inlet.radius", K::real, "1.0", "mm", 1e-9, 1e6, {},
               "the circle's radius (about the axis through inlet.center along "
               "inlet.direction)", "inlet.profile=parabolic,inlet.section=circle"});
  k.push_back({"inlet.ramp_time", K::real, "0.0", "ms", 0, 1e7, {},
               "the speed rises as (1 - cos(pi t / ramp_time)) / 2 to its value at "
               "ramp_time, then holds (0: at once)"});
  only_when(k, inlet_keys, "mesh.source=file,puff.load=air|fsi");
  // the mesh motion (puff.load = "fsi"), forms/mesh_motion.py
  const std::size_t fsi_keys = k.size();
  k.push_back({"mesh_motion.model", K::choice, "\"elastic\"", "", -inf, inf,
               {"harmonic", "elastic"},
               "extension of the interface's displacement into the air: harmonic = each "
               "component's Laplace equation, elastic = a linear pseudo-solid; both with "
               "Jacobian-based stiffening (Stein, Tezduyar & Benney 2003)"});
  k.push_back({"mesh_motion.stiffening", K::real, "1.0", "", 0, 5, {},
               "power chi of the stiffening (J_0 / J_cell)^chi: small cells deform less; "
               "0 switches it off"});
  k.push_back({"mesh_motion.poisson_ratio", K::real, "0.3", "", 0, 0.49, {},
               "Poisson's ratio of the elastic extension",
               "puff.load=fsi,mesh_motion.model=elastic"});
  k.push_back({"mesh_motion.distance", K::real, "3.0", "mm", 0.05, 1e3, {},
               "only the air within this distance of the eye's surface moves; the rest of "
               "the air mesh is fixed and carries no mesh-motion unknowns"});
  // the coupling (puff.load = "fsi"), cpp/fsi
  k.push_back({"fsi.shape_derivative", K::boolean, "true", "", -inf, inf, {},
               "the Jacobian holds the air residual's derivative with respect to the mesh "
               "motion (exact Newton); false leaves it out (fewer entries, more iterations)"});
  k.push_back({"fsi.linear_solver", K::choice, "\"lu\"", "", -inf, inf,
               {"lu", "fieldsplit"},
               "lu = MUMPS on the whole coupled system; fieldsplit = FGMRES preconditioned "
               "by block Gauss-Seidel over the solid and the air with the mesh motion, "
               "each block's LU kept across iterations and steps"});
  only_when(k, fsi_keys, "puff.load=fsi");
  // nonlinear and linear solver
  k.push_back({"solver.max_iterations", K::integer, "25", "", 1, 500, {},
               "Newton iterations per load step before the step is cut"});
  k.push_back({"solver.rtol", K::real, "1e-9", "", 1e-16, 1e-1, {},
               "Newton: residual norm relative to the step's first residual"});
  k.push_back({"solver.atol", K::real, "1e-11", "N", 0, 1, {},
               "Newton: absolute residual norm"});
  k.push_back({"solver.line_search", K::choice, "\"energy\"", "", -inf, inf,
               {"energy", "none"},
               "Newton step length: energy = secant search for the zero of the "
               "residual projected on the step (non-finite residuals halve it); "
               "none = full steps"});
  k.push_back({"solver.jacobian", K::choice, "\"reuse\"", "", -inf, inf,
               {"reuse", "every_iteration", "krylov"},
               "reuse = keep the factorised Jacobian while each Newton iteration cuts the "
               "residual by solver.reuse_contraction (modified Newton, fewer factorisations); every_iteration = "
               "full Newton (quadratic convergence, a factorisation per iteration); krylov = "
               "full Newton whose linear solves are GMRES preconditioned by the last "
               "factorisation, refactorised when GMRES needs more than "
               "solver.krylov_refactorise iterations"});
  k.push_back({"solver.reuse_contraction", K::real, "0.7", "", 0.01, 0.99, {},
               "solver.jacobian = reuse: refactorise once a Newton iteration (after a solve's "
               "first) cuts the residual norm by less than this factor (0.7 with the Anderson "
               "acceleration, which keeps a factorisation longer; 0.25 without)"});
  k.push_back({"solver.factorisation", K::choice, "\"lu\"", "", -inf, inf, {"lu", "ldlt"},
               "the solid's factorised Jacobian: lu = MUMPS LU of the Jacobian (Newton "
               "converges quadratically with a fresh one, also near limit points); ldlt = "
               "MUMPS LDL^T of its upper triangle taken as symmetric, a third cheaper to "
               "factorise and half to assemble, the follower pressures' skew part left to "
               "the iteration (linear convergence; it can stall near a limit load or with "
               "nearly incompressible parts); not with solver.jacobian = krylov"});
  k.push_back({"solver.reuse_iterations", K::integer, "1000", "", 1, 1000, {},
               "solver.jacobian = reuse: refactorise after this many iterations on one "
               "factorisation within a solve"});
  k.push_back({"solver.anderson", K::integer, "5", "", 0, 50, {},
               "solver.jacobian = reuse: Anderson acceleration of the iteration on the kept "
               "factorisation over this many past steps (nonlinear GMRES; Walker & Ni 2011); "
               "0 = plain modified Newton"});
  k.push_back({"solver.krylov_refactorise", K::integer, "10", "", 1, 1000, {},
               "solver.jacobian = krylov: refactorise the preconditioner once a linear solve "
               "needs more GMRES iterations than this"});
  k.push_back({"solver.predictor", K::choice, "\"extrapolate\"", "", -inf, inf,
               {"previous", "extrapolate"},
               "a step's first Newton iterate: previous = the last converged state; "
               "extrapolate = a load ramp's secant through the last two, the solid's "
               "time step's constant-acceleration state u_n + dt v_n + dt^2/2 a_n (the "
               "air's and the coupled system's: the secant)"});
  k.push_back({"solver.increment_tol", K::real, "0", "mm", 0, 1, {},
               "Newton also converges when its error estimate from the last two steps, "
               "|dx| q/(1-q) with q the steps' ratio (max norm, the unknowns' units: mm, mm/ms, "
               "MPa), is below this; 0 = off (the residual tests only)"});
  k.push_back({"solver.max_growth", K::real, "1e4", "", 2, 1e12, {},
               "Newton counts as diverging (and the step is cut) once the residual norm "
               "exceeds this multiple of its smallest value in the solve"});
  k.push_back({"solver.max_step_cuts", K::integer, "8", "", 0, 30, {},
               "a failed load step is halved, down to 2^-max_step_cuts of the nominal step; "
               "failing there stops the run"});
  k.push_back({"solver.petsc", K::options, "{}", "", -inf, inf, {},
               "PETSc options for the linear solver (default: MUMPS LU), e.g. "
               "ksp_type = \"cg\""});
  // checkpoint: the whole state every few steps of the dynamics, to resume from
  k.push_back({"checkpoint.steps", K::integer, "0", "", 0, 100000, {},
               "every this many time steps of a march (rest, puff) is a checkpoint "
               "boundary: the Newton solver drops its kept factorisation there, and the "
               "whole state may be written to <out>/checkpoint for nct run --resume; 0 = off"});
  k.push_back({"checkpoint.minutes", K::real, "0", "min", 0, 1e5, {},
               "write at a boundary only once this much wall time has passed since the "
               "last write (0 = at every boundary); the results do not depend on it "
               "(only with checkpoint.steps > 0)"});
  k.push_back({"checkpoint.keep", K::integer, "2", "", 1, 1000, {},
               "checkpoint files kept (the newest); older ones are deleted "
               "(only with checkpoint.steps > 0)"});
  // output
  k.push_back({"output.fields", K::boolean, "true", "", -inf, inf, {},
               "write XDMF fields (displacement, fibres, von Mises stress)"});
  k.push_back({"output.probes", K::points, "[]", "mm", -inf, inf, {},
               "reference points whose displacement is reported at each step "
               "(the eye adds its apex)"});
  k.push_back({"output.force_on", K::strings, "[]", "", -inf, inf, {},
               "file: facet groups (walls and the interface) whose fluid force, summed "
               "node by node, is reported at each step (forces.csv, steps.csv's "
               "air_force_*_N, summary.json's air.force_N; e.g. a body's drag and lift)",
               "mesh.source=file,puff.load=air|fsi"});
  return k;
}

} // namespace

const std::vector<Key>& keys()
{
  static const std::vector<Key> all = declare();
  return all;
}

void check_consistency(const Scene& s)
{
  const std::string file = s.file().string();
  const bool eye = s.string("mesh.source") == "eye";
  auto fail = [&](const std::string& what)
  { throw Error(file + ": " + what); };

  // The biomarkers need the deepest frame and its neighbours.
  const std::string load = s.string("puff.load");
  if ((load == "gaussian" || load == "pulse" || load == "table" || load == "fsi")
      && s.real("puff.duration") * s.real("puff.frame_rate") < 2e3)
    fail("key 'puff.duration': " + std::to_string(s.real("puff.duration"))
         + " ms holds fewer than 3 frames at puff.frame_rate = "
         + std::to_string(s.real("puff.frame_rate")) + "/s; needs at least "
         + std::to_string(2e3 / s.real("puff.frame_rate")) + " ms");

  if (s.string("solver.factorisation") == "ldlt" && s.string("solver.jacobian") == "krylov")
    fail("key 'solver.factorisation': \"ldlt\" factorises the symmetric part only, but "
         "solver.jacobian = \"krylov\" needs the Jacobian itself: \"lu\"");

  if (s.string("support.model") == "springs")
  {
    if (!eye && s.strings("boundary.fixed").empty())
      fail("key 'support.model': \"springs\" act on boundary.fixed, which names no group");
  }

  if (load == "air" && !eye)
    for (const std::string& part : s.tables("material"))
      if (s.string("material." + part + ".model") != "fluid")
        fail("key 'puff.load': \"air\" on a file mesh is its fluid alone, but '" + part
             + "' is a solid (material." + part + ".model); the fluid and a solid run "
             "coupled: \"fsi\"");

  if (eye)
    for (const std::string& part : s.tables("material"))
      if (s.string("material." + part + ".model") == "fluid")
        fail("key 'material." + part + ".model': \"fluid\" is for a file mesh's volume "
             "groups; the eye's air is the nozzle's (puff.load = \"air\" or \"fsi\")");
  if (!eye)
  {
    if (s.string("mesh.file").empty())
      fail("key 'mesh.file': mesh.source = \"file\" needs a mesh file");
    auto mesh = s.path("mesh.file");
    std::error_code ec; // e.g. a name too long
    if (!std::filesystem::is_regular_file(mesh, ec))
      fail("key 'mesh.file': file '" + s.string("mesh.file")
           + "' not found (looked for " + mesh.string() + ")");
    auto ext = mesh.extension().string();
    if (ext != ".msh" && ext != ".geo")
      fail("key 'mesh.file': '" + ext + "' files are not read; accepted: .msh, .geo");
    if (ext == ".msh" && s.real("mesh.size_max") > 0)
      fail("key 'mesh.size_max' applies when nct meshes a .geo; '"
           + s.string("mesh.file") + "' is already meshed");
    if (s.tables("material").empty())
      fail("key 'material': a file mesh needs a [material.<group>] table per "
           "volume group");
    // A fluid part is the coupled run's fluid, and that needs one.
    std::vector<std::string> fluids;
    for (const std::string& part : s.tables("material"))
      if (s.string("material." + part + ".model") == "fluid")
        fluids.push_back(part);
    if (load == "fsi" && fluids.empty())
      fail("key 'puff.load': \"fsi\" on a file mesh needs a fluid volume group (a "
           "[material.<group>] with model = \"fluid\")");
    const bool flow = load == "fsi" || load == "air";
    if (!flow && !fluids.empty())
      fail("key 'material." + fluids[0] + ".model': a fluid part exists only in a run of "
           "the fluid (puff.load = \"fsi\" with a solid, \"air\" alone)");
    if (load == "fsi" && fluids.size() == s.tables("material").size())
      fail("key 'material': every volume group is fluid; the coupled run needs a solid "
           "(the fluid alone: puff.load = \"air\")");
    if (!flow)
      for (const char* b : {"inlet", "outlet", "wall", "interface"})
        if (!s.strings(std::string("boundary.") + b).empty())
          fail(std::string("key 'boundary.") + b + "': a fluid boundary; it needs a fluid "
               "part and puff.load = \"fsi\" or \"air\"");
    if (load == "air" && !s.strings("boundary.interface").empty())
      fail("key 'boundary.interface': the fluid alone (puff.load = \"air\") has no "
           "interface");
    // A group has one boundary condition.
    std::map<std::string, std::string> owner;
    for (const char* b : {"fixed", "symmetry", "cavity_wall", "surface_load", "inlet", "outlet",
                          "wall", "interface"})
      for (const std::string& g : s.strings(std::string("boundary.") + b))
      {
        auto [it, fresh] = owner.emplace(g, b);
        if (!fresh)
          fail("group '" + g + "' is in both boundary." + it->second
               + " and boundary." + b + ": a facet group has one condition");
      }
    if (s.real("inflate.iop") > 0 && s.strings("boundary.cavity_wall").empty())
      fail("key 'inflate.iop' > 0 but boundary.cavity_wall names no group");
    if (s.real("press.pressure") != 0 && s.strings("boundary.surface_load").empty())
      fail("key 'press.pressure' != 0 but boundary.surface_load names no group");
    if (!flow && load != "none" && s.strings("boundary.surface_load").empty())
      fail("key 'puff.load' is not \"none\" but boundary.surface_load names no group");
    for (const std::string& part : s.tables("material"))
      if (s.points("material." + part + ".fibre_directions").size() > 2)
        fail("key 'material." + part
             + ".fibre_directions': at most two fibre families");
  }
}

} // namespace nct::scene
