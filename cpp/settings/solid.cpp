// The solid block: [material.<part>], [fem], [support], [cavity],
// [zero_pressure], [inflate], [press], [rest], output.probes.
#include "settings/settings.h"

#include <tuple>

namespace nct
{
namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();
} // namespace

namespace solid
{

void visit(scene::Visitor& v, Material& m, const std::string& part)
{
  // Defaults by part. The internal structures' E (docs/physics.md section
  // 5): "linear elastic" taken as the compressible neo-Hookean (Hooke's
  // law at small strain, stable in compression). The lens is nearly
  // incompressible: nu = 0.49, as in the lens models since Fisher (J
  // Physiol 212 (1971) 147) and Burd et al. (Vision Res 42 (2002) 2235);
  // it keeps the soft nucleus' bulk modulus (5 kPa, 37 mmHg) above the
  // IOP. The thin zonule and membrane keep 0.45 (their volume change does
  // not matter).
  struct Defaults
  {
    const char *model, *c10, *k1, *k2, *kappa, *youngs_modulus, *poisson_ratio, *when;
  };
  static const std::map<std::string, Defaults> by_part = {
      {"cornea", {"hgo", "0.05", "0.010", "100", "5.0", "1.0", "0.3", "mesh.source=eye"}},
      {"limbus", {"hgo", "0.05", "0.010", "100", "5.0", "1.0", "0.3", "mesh.source=eye"}},
      {"sclera", {"neo_hookean", "0.8", "0", "1", "80.0", "1.0", "0.3", "mesh.source=eye"}},
      {"lens_cortex",
       {"compressible_neo_hookean", "0.05", "0", "1", "5.0", "0.35", "0.49",
        "mesh.source=eye,geometry.internal_structures=true"}},
      {"lens_nucleus",
       {"compressible_neo_hookean", "0.05", "0", "1", "5.0", "0.0003", "0.49",
        "mesh.source=eye,geometry.internal_structures=true"}},
      {"zonule",
       {"compressible_neo_hookean", "0.05", "0", "1", "5.0", "0.35", "0.45",
        "mesh.source=eye,geometry.internal_structures=true"}},
      {"vitreous_membrane",
       {"compressible_neo_hookean", "0.05", "0", "1", "5.0", "0.35", "0.45",
        "mesh.source=eye,geometry.internal_structures=true"}},
      {"*", {"neo_hookean", "0.5", "0", "1", "50.0", "1.0", "0.3", "mesh.source=file"}}};
  auto it = by_part.find(part);
  const Defaults& d = it != by_part.end() ? it->second : by_part.at("*");
  const bool file = it == by_part.end() || part == "*";
  const std::string k = "material." + part + ".";
  v.choice({k + "model", d.model, "", -inf, inf,
            "material law of the part: hgo, neo_hookean (nearly incompressible, C10 and kappa), "
            "compressible_neo_hookean (E and nu: Hooke's law at small strain, stable in "
            "compression), saint_venant_kirchhoff (E and nu: linear in the Green-Lagrange "
            "strain, softens and collapses in compression), or fluid (file meshes with puff.load "
            "= \"fsi\": the part is incompressible Newtonian fluid, the air block's "
            "Navier-Stokes)",
            d.when},
           m.law,
           {{"hgo", Law::hgo},
            {"neo_hookean", Law::neo_hookean},
            {"compressible_neo_hookean", Law::compressible_neo_hookean},
            {"saint_venant_kirchhoff", Law::saint_venant_kirchhoff},
            {"fluid", Law::fluid}});
  v.real({k + "c10", d.c10, "MPa", 1e-6, 1e5,
          "matrix stiffness C10 (hgo, neo_hookean); shear modulus 2 C10", d.when},
         m.c10);
  v.real({k + "k1", d.k1, "MPa", 0, 1e3, "fibre stiffness k1 (hgo); 0 makes the part isotropic",
          d.when},
         m.k1);
  v.real({k + "k2", d.k2, "", 1e-3, 1e4, "fibre nonlinearity k2 (hgo)", d.when}, m.k2);
  v.real({k + "dispersion", "0", "", 0, 1.0 / 3,
          "fibre dispersion kappa_f of Gasser, Ogden and Holzapfel 2006 (hgo): 0 = fibres "
          "aligned with their directions (the 2000 law), 1/3 = isotropic",
          d.when},
         m.dispersion);
  v.reals({k + "viscoelasticity.relative_moduli", "[]", "", 0, 1e3,
           "viscoelasticity of the matrix (hgo, neo_hookean; forms/viscoelasticity.py): each "
           "Prony term's modulus beta_k relative to the long-time one, so that a sudden strain "
           "meets (1 + sum beta_k) C10; none: elastic",
           d.when},
          m.relative_moduli);
  v.reals({k + "viscoelasticity.relaxation_times", "[]", "ms", 1e-6, 1e9,
           "each Prony term's relaxation time tau_k, as many as relative_moduli", d.when},
          m.relaxation_times);
  v.real({k + "kappa", d.kappa, "MPa", 1e-3, 1e7,
          "bulk modulus of the volumetric penalty (hgo, neo_hookean)", d.when},
         m.kappa);
  v.real({k + "youngs_modulus", d.youngs_modulus, "MPa", 1e-9, 1e5,
          "Young's modulus E (compressible_neo_hookean, saint_venant_kirchhoff)", d.when},
         m.youngs_modulus);
  v.real({k + "poisson_ratio", d.poisson_ratio, "", 0, 0.499,
          "Poisson's ratio nu (compressible_neo_hookean, saint_venant_kirchhoff); bulk modulus "
          "E / (3 (1 - 2 nu))",
          d.when},
         m.poisson_ratio);
  v.real({k + "density", "0.0011", "g/mm^3", 1e-9, 1e3,
          "mass density (dynamic phases; a fluid's density)", d.when},
         m.density);
  m.viscosity = 0;
  m.fibre_directions.clear();
  if (!file)
    return;
  v.real({k + "viscosity", "1.8e-8", "MPa ms", 1e-12, 1e3, "dynamic viscosity (fluid)", d.when},
         m.viscosity);
  v.points({k + "fibre_directions", "[]", "", -inf, inf,
            "up to two constant fibre directions (hgo), normalised on use; none makes the part "
            "isotropic",
            d.when},
           m.fibre_directions);
}

} // namespace solid

void visit(scene::Visitor& v, SolidSettings& s)
{
  v.integer({"fem.degree", "2", "", 1, 2, "polynomial degree of the displacement (Lagrange)"},
            s.element.degree);
  v.choice({"fem.quadrature", "reduced", "", -inf, inf,
            "cell quadrature: reduced = degree 2(p-1), at least 1 (the 1- and 4-point rules of "
            "the standard linear and quadratic tetrahedra, exact for linear elasticity); full = "
            "degree 2p, about 3x dearer assembly at p = 2"},
           s.element.reduced_quadrature, {{"reduced", true}, {"full", false}});
  v.choice({"fem.formulation", "displacement", "", -inf, inf,
            "displacement = u only: the volumetric energy kappa/2 (ln J)^2 at every quadrature "
            "point (locks as kappa/mu grows); mixed = displacement-pressure P2/P0, the pressure "
            "constant per cell and condensed out (the volumetric energy at the centroid): no "
            "locking; needs fem.degree = 2"},
           s.element.mixed, {{"displacement", false}, {"mixed", true}});
  v.points({"cavity.origin", "[[0.0, 0.0, 0.0]]", "mm", -inf, inf,
            "file: point on every symmetry plane and on any flat closing cap; the cavity volume "
            "is taken about it",
            "mesh.source=file"},
           s.cavity.origin);
  // the support of the fixed face (the eye's cut, a file's boundary.fixed)
  v.choice({"support.model", "clamped", "", -inf, inf,
            "clamped = u = 0 throughout; springs = clamped in the quasi-static phases, then from "
            "the start of the dynamics held by springs and dashpots (forms/support.py) that take "
            "over the clamp's reaction: the whole eye moves in the orbit"},
           s.support.springs, {{"clamped", false}, {"springs", true}});
  v.real({"support.stiffness", "0.35", "N/mm", 1e-9, 1e6,
          "the whole model's spring stiffness, spread evenly over the fixed face (Kling et al. "
          "2014, table 3: 350 N/m for the human eye)",
          "support.model=springs"},
         s.support.stiffness);
  v.real({"support.damping", "100.0", "N ms/mm", 0, 1e6,
          "the whole model's dashpot, spread evenly over the fixed face (Kling et al. 2014, "
          "table 3: 100 kg/s = 100 N ms/mm)",
          "support.model=springs"},
         s.support.damping);
  // the fluid cavities (humors)
  v.choice({"cavity.model", "closed", "", -inf, inf,
            "after inflation: closed = each cavity keeps its volume and its pressure is an "
            "unknown (incompressible humor); constant_pressure = the pressure stays at the IOP "
            "(open system)"},
           s.cavity.closed, {{"closed", true}, {"constant_pressure", false}});
  v.choice({"cavity.humor_inertia", "none", "", -inf, inf,
            "the humors' mass in the dynamics: none = massless; translation = each closed "
            "cavity's humor moves as its centroid does, the wall carrying its inertial force "
            "as a pressure linear in position (forms/humor_inertia.py; its flow relative to the "
            "centroid is left out); flow = each closed cavity's humor is meshed and flows, "
            "inviscid and incompressible, as the wall drives it: a pressure field on the "
            "humor's mesh (forms/humor_flow.py); navier_stokes = the humor meshed as the "
            "air is, viscous incompressible Navier-Stokes in ALE form two-way coupled to the "
            "wall (forms/air_ale.py, cpp/fsi): the full equations the flow model leaves out, "
            "for checking it (a prescribed puff, the cut clamped)"},
           s.cavity.humor_inertia,
           {{"none", CavitySettings::HumorInertia::none},
            {"translation", CavitySettings::HumorInertia::translation},
            {"flow", CavitySettings::HumorInertia::flow},
            {"navier_stokes", CavitySettings::HumorInertia::navier_stokes}});
  v.real({"cavity.humor_density", "1.0e-3", "g/mm^3", 1e-6, 0.1,
          "density of the humors: water's, of which the aqueous and the vitreous are 98-99 %",
          "cavity.humor_inertia=translation|flow|navier_stokes"},
         s.cavity.humor_density);
  v.real({"cavity.humor_viscosity", "0.7e-6", "MPa ms", 1e-12, 1,
          "dynamic viscosity of the humors as Navier-Stokes: the aqueous', 0.7 mPa s at 37 C "
          "(about water's; the vitreous gel's shear modulus of a few Pa is left out)",
          "cavity.humor_inertia=navier_stokes"},
         s.cavity.humor_viscosity);
  v.strings({"cavity.humor_groups", "[]", "", -inf, inf,
             "file: the volume groups of the cavity's humor, meshed conforming to "
             "boundary.cavity_wall: its mesh with cavity.humor_inertia = \"flow\" or "
             "\"navier_stokes\", left out "
             "with the other models",
             "mesh.source=file"},
            s.cavity.humor_groups);
  // phase: zero-pressure geometry
  auto& zp = s.zero_pressure;
  const std::string zero_pressure = "zero_pressure.enabled=true";
  v.boolean({"zero_pressure.enabled", "false", "", -inf, inf,
             "take the mesh as the eye imaged at inflate.iop and first find its stress-free "
             "geometry (backward-displacement fixed point)"},
            zp.enabled);
  v.real({"zero_pressure.tolerance", "1e-4", "mm", 1e-10, 1,
          "stop when no node of the pressurised stress-free geometry is farther than this from "
          "the imaged one",
          zero_pressure},
         zp.fixed_point.tolerance);
  v.integer({"zero_pressure.max_iterations", "30", "", 1, 500,
             "fixed-point iterations before the run stops", zero_pressure},
            zp.fixed_point.max_iterations);
  v.choice({"zero_pressure.acceleration", "aitken", "", -inf, inf,
            "aitken = dynamic relaxation of each update (Irons-Tuck); none = the plain fixed "
            "point X -= x(X) - x_imaged",
            zero_pressure},
           zp.fixed_point.aitken, {{"aitken", true}, {"none", false}});
  v.choice({"zero_pressure.round_trip", "reuse", "", -inf, inf,
            "the inflate phase after zero pressure: reuse = one step from the fixed point's last "
            "pressurised state (the inflated stress-free geometry); ramp = inflate the "
            "stress-free geometry again from rest in inflate.steps, an independent round trip at "
            "the ramp's cost",
            zero_pressure},
           zp.reuse, {{"reuse", true}, {"ramp", false}});
  // phase: inflation
  v.real({"inflate.iop", "15.0", "mmHg", 0, 200,
          "intraocular pressure reached at the end of the inflation ramp"},
         s.cavity.iop);
  v.integer({"inflate.steps", "5", "", 1, 10000, "load steps of the linear pressure ramp from zero"},
            s.cavity.inflate_steps);
  // phase: press (a static follower pressure, after inflation and closing)
  v.real({"press.pressure", "0.0", "mmHg", -1e6, 1e6,
          "peak follower pressure on the pressed surface (the eye: the anterior cornea; a file "
          "mesh: boundary.press); negative pulls; 0 skips the phase"},
         s.press.pressure);
  v.integer({"press.steps", "5", "", 1, 10000, "load steps of the linear ramp from zero"},
            s.press.steps);
  v.choice({"press.profile", "uniform", "", -inf, inf,
            "shape across the surface: uniform, or gaussian in the distance r from the y axis, "
            "exp(-r^2 / (2 width^2))"},
           s.press.gaussian, {{"uniform", false}, {"gaussian", true}});
  v.real({"press.width", "1.5", "mm", 1e-3, 1e3, "standard deviation of the gaussian profile",
          "press.profile=gaussian"},
         s.press.width);
  // phase: rest (dynamic, loads held)
  v.real({"rest.duration", "0.0", "ms", 0, 1e3,
          "time the closed, inflated eye is followed before the puff with the loads held (it "
          "should not move); 0 skips the phase"},
         s.rest_duration);
  v.points({"output.probes", "[]", "mm", -inf, inf,
            "reference points whose displacement is reported at each step (probes.csv and "
            "summary.json; the eye adds its apex)"},
           s.probes);
}

void visit(scene::Visitor& v, CheckpointSettings& s)
{
  v.integer({"checkpoint.steps", "0", "", 0, 100000,
             "every this many time steps of a march (rest, puff) is a checkpoint boundary: the "
             "Newton solver drops its kept factorisation there, and the whole state may be "
             "written to <out>/checkpoint for nct run --resume; 0 = off"},
            s.steps);
  v.real({"checkpoint.minutes", "0", "min", 0, 1e5,
          "write at a boundary only once this much wall time has passed since the last write (0 "
          "= at every boundary); the results do not depend on it (only with checkpoint.steps > "
          "0)"},
         s.minutes);
  v.integer({"checkpoint.keep", "2", "", 1, 1000,
             "checkpoint files kept (the newest); older ones are deleted (only with "
             "checkpoint.steps > 0)"},
            s.keep);
}

void visit(scene::Visitor& v, OutputSettings& s)
{
  v.boolean({"output.fields", "true", "", -inf, inf,
             "write XDMF fields (displacement, fibres, von Mises stress)"},
            s.fields);
}

} // namespace nct
