// The air block: [air] (stabilised ALE Navier-Stokes, forms/air.py and
// forms/air_ale.py; the nozzle's domain), [inlet], output.force_on; the
// mesh motion ([mesh_motion], forms/mesh_motion.py) and the coupling
// ([fsi], cpp/fsi).
#include "settings/settings.h"

namespace nct
{
namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();
const std::string nozzle = "mesh.source=eye,puff.load=air|fsi"; // the eye's air; a file's: material.*
const std::string flow = "puff.load=air|fsi";
const std::string file_flow = "mesh.source=file,puff.load=air|fsi";
} // namespace

namespace air
{

void visit(scene::Visitor& v, Fluid& f)
{
  v.real({"air.density", "1.25e-6", "g/mm^3", 1e-9, 1e-2, "air density", nozzle}, f.density);
  v.real({"air.viscosity", "1.8e-8", "MPa ms", 1e-12, 1, "air dynamic viscosity", nozzle},
         f.viscosity);
  v.real({"air.backflow", "1.0", "", 0, 10,
          "outlet backflow stabilisation beta (>= 0.5 is energy stable; 0 turns it off)", flow},
         f.backflow);
  v.real({"air.stabilisation_time", "0.25", "ms", 1e-4, 1e3,
          "time scale T of the stabilisation parameter tau_M = (4/T^2 + a.G a + ...)^-1/2: "
          "fixed, not the time step, so that the time steps converge to one solution; it bounds "
          "tau where the air is still (forms/navier_stokes.py)",
          flow},
         f.stabilisation_time);
}

void visit(scene::Visitor& v, Domain& d)
{
  v.real({"air.radius", "50.0", "mm", 5, 500, "radius of the air domain about the optical axis",
          nozzle},
         d.radius);
  v.real({"air.nozzle_diameter", "2.4", "mm", 0.1, 20, "inner diameter of the nozzle (its bore)",
          nozzle},
         d.nozzle_diameter);
  v.real({"air.nozzle_outer_diameter", "6.0", "mm", 0.2, 100,
          "outer diameter of the nozzle's tube", nozzle},
         d.nozzle_outer_diameter);
  v.real({"air.nozzle_distance", "11.0", "mm", 1, 100,
          "distance from the nozzle's exit to the corneal apex, along the axis", nozzle},
         d.nozzle_distance);
  v.real({"air.nozzle_length", "2.0", "mm", 0.5, 200,
          "length of the bore from the inlet (the device's face) to the exit", nozzle},
         d.nozzle_length);
  v.real({"air.size_nozzle", "0.1", "mm", 0.005, 10,
          "element size in the nozzle's bore and one bore radius beyond its exit", nozzle},
         d.size_nozzle);
  v.real({"air.size_jet", "0.15", "mm", 0.005, 10,
          "element size within air.jet_radius of the axis, from the inlet to the eye", nozzle},
         d.size_jet);
  v.real({"air.jet_radius", "2.0", "mm", 0.1, 50, "radius of the finely meshed core about the axis",
          nozzle},
         d.jet_radius);
  v.real({"air.size_far", "5.0", "mm", 0.05, 100,
          "largest element size (sizes grow by air.size_gradation away from the core)", nozzle},
         d.size_far);
  v.real({"air.size_gradation", "0.25", "mm/mm", 0.01, 2,
          "growth of the element size per mm of distance from the nozzle and the jet's core; "
          "a mesh study halves it with air.size_jet and air.size_nozzle to refine everywhere",
          nozzle},
         d.size_gradation);
}

} // namespace air

void visit(scene::Visitor& v, AirSettings& s)
{
  v.choice({"air.eye", "rigid", "", -inf, inf,
            "rigid = the idealised eye (geometry.*, mesh.*) is a fixed no-slip wall in the air; "
            "none = the free jet, the eye's place left to the air",
            "mesh.source=eye,puff.load=air"},
           s.rigid_eye, {{"rigid", true}, {"none", false}});
  visit(v, s.fluid);
  v.integer({"air.bdf_order", "2", "", 1, 2,
             "order of the backward differentiation formula in time (the first step: 1)", flow},
            s.bdf_order);
  v.real({"air.output_interval", "1.0", "ms", 1e-5, 1e5,
          "time between the XDMF velocity and pressure fields (output.fields)", flow},
         s.output_interval);
  visit(v, s.domain);
  visit(v, s.inlet);
  v.strings({"output.force_on", "[]", "", -inf, inf,
             "file: facet groups (walls and the interface) whose fluid force, summed node by "
             "node, is reported at each step (forces.csv, steps.csv's air_force_*_N, "
             "summary.json's air.force_N; e.g. a body's drag and lift)",
             file_flow},
            s.force_on);
}

void visit(scene::Visitor& v, InletSettings& s)
{
  using P = InletSettings::Profile;
  v.real({"inlet.velocity", "120.0", "m/s", 0, 1e3,
          "the profile's largest speed (on the axis or centre line) at the peak of the puff "
          "(the eye's nozzle) or once ramped (a file mesh)",
          "puff.load=air|fsi,inlet.profile=uniform|parabolic"},
         s.velocity);
  v.choice({"inlet.profile", "uniform", "", -inf, inf,
            "across the inlet: uniform; parabolic: on the eye 1 - (r / bore radius)^2 across "
            "the nozzle's bore (half the flow rate), on a file mesh over inlet.section: a "
            "rectangle prod_i (1 - (s_i / a_i)^2) (s_i along inlet.axes from inlet.center, a_i "
            "= inlet.half_width_i; inf: no variation that way, a channel or a slab) or a circle "
            "1 - (r / inlet.radius)^2; table (file meshes): speeds at points (inlet.table), "
            "between them their inverse distance weighted mean (Shepard, power 2)",
            flow},
           s.profile, {{"uniform", P::uniform}, {"parabolic", P::parabolic}, {"table", P::table}});
  v.choice({"inlet.history", "gaussian", "", -inf, inf,
            "the nozzle's speed in time: gaussian = inlet.velocity exp(-(t - puff.peak_time)^2 "
            "/ (2 puff.width_t^2)); pulse = inlet.velocity sqrt(s(t)), s the measured pulse's "
            "shape (puff.peak, rise_rate, fall_rate, pulse_duration): the quasi-steady jet's "
            "stagnation pressure follows s (a file mesh's inlet: inlet.ramp_time)",
            nozzle},
           s.pulse, {{"gaussian", false}, {"pulse", true}});
  v.points({"inlet.direction", "[]", "", -inf, inf,
            "file: the flow's direction at the inlet; none: the inlet's inward normal (a plane "
            "inlet)",
            file_flow},
           s.direction);
  v.path({"inlet.table", "", "", -inf, inf,
          "file: CSV file with the header x_mm,y_mm,z_mm,u_m_s (the speed along inlet.direction "
          "once ramped), relative to the scene file",
          file_flow + ",inlet.profile=table"},
         s.table);
  v.choice({"inlet.section", "rectangle", "", -inf, inf, "file: the parabolic profile's section",
            file_flow + ",inlet.profile=parabolic"},
           s.circle, {{"rectangle", false}, {"circle", true}});
  v.points({"inlet.center", "[[0.0, 0.0, 0.0]]", "mm", -inf, inf,
            "file: the section's centre (on the inlet)", file_flow + ",inlet.profile=parabolic"},
           s.center);
  const std::string rectangle = file_flow + ",inlet.profile=parabolic,inlet.section=rectangle";
  v.points({"inlet.axes", "[[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]", "", -inf, inf,
            "file: two directions across the rectangle (normalised on use)", rectangle},
           s.axes);
  v.real({"inlet.half_width_1", "inf", "mm", 1e-9, inf,
          "file: the rectangle's half width along the inlet.axes' vector 1 (inf: unbounded, no "
          "variation that way)",
          rectangle},
         s.half_width_1);
  v.real({"inlet.half_width_2", "inf", "mm", 1e-9, inf,
          "file: the rectangle's half width along the inlet.axes' vector 2 (inf: unbounded, no "
          "variation that way)",
          rectangle},
         s.half_width_2);
  v.real({"inlet.radius", "1.0", "mm", 1e-9, 1e6,
          "file: the circle's radius (about the axis through inlet.center along "
          "inlet.direction)",
          file_flow + ",inlet.profile=parabolic,inlet.section=circle"},
         s.radius);
  v.real({"inlet.ramp_time", "0.0", "ms", 0, 1e7,
          "file: the speed rises as (1 - cos(pi t / ramp_time)) / 2 to its value at ramp_time, "
          "then holds (0: at once)",
          file_flow},
         s.ramp_time);
}

namespace mesh_motion
{

void visit(scene::Visitor& v, Settings& s)
{
  const std::string fsi = "puff.load=fsi";
  v.choice({"mesh_motion.model", "elastic", "", -inf, inf,
            "extension of the interface's displacement into the air: harmonic = each "
            "component's Laplace equation, elastic = a linear pseudo-solid; both with "
            "Jacobian-based stiffening (Stein, Tezduyar & Benney 2003)",
            fsi},
           s.model, {{"harmonic", std::string("harmonic")}, {"elastic", std::string("elastic")}});
  v.real({"mesh_motion.stiffening", "1.0", "", 0, 5,
          "power chi of the stiffening (J_0 / J_cell)^chi: small cells deform less; 0 switches "
          "it off",
          fsi},
         s.stiffening);
  v.real({"mesh_motion.poisson_ratio", "0.3", "", 0, 0.49,
          "Poisson's ratio of the elastic extension", "puff.load=fsi,mesh_motion.model=elastic"},
         s.poisson_ratio);
  v.real({"mesh_motion.distance", "3.0", "mm", 0.05, 1e3,
          "only the air within this distance of the eye's surface moves; the rest of the air "
          "mesh is fixed and carries no mesh-motion unknowns",
          fsi},
         s.distance);
}

} // namespace mesh_motion

void visit(scene::Visitor& v, FsiSettings& s)
{
  const std::string fsi = "puff.load=fsi";
  v.boolean({"fsi.shape_derivative", "true", "", -inf, inf,
             "the Jacobian holds the air residual's derivative with respect to the mesh motion "
             "(exact Newton); false leaves it out (fewer entries, more iterations)",
             fsi},
            s.shape_derivative);
  v.choice({"fsi.linear_solver", "lu", "", -inf, inf,
            "lu = MUMPS on the whole coupled system; fieldsplit = FGMRES preconditioned by block "
            "Gauss-Seidel over the solid and the air with the mesh motion, each block's LU kept "
            "across iterations and steps",
            fsi},
           s.fieldsplit, {{"lu", false}, {"fieldsplit", true}});
}

} // namespace nct
