// The model's meshes: [mesh], [geometry], a file mesh's [boundary].
#include "settings/settings.h"

namespace nct
{
namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();
const std::string on_file = "mesh.source=file";
const std::string on_eye = "mesh.source=eye";
const std::string on_internal = "mesh.source=eye,geometry.internal_structures=true";
} // namespace

void visit(scene::Visitor& v, MeshSettings& s)
{
  v.choice({"mesh.source", "eye", "", -inf, inf,
            "the parametric idealised eye, or an external gmsh mesh (mesh.file)"},
           s.source, {{"eye", MeshSettings::Source::eye}, {"file", MeshSettings::Source::file}});
  v.choice({"mesh.dimension", "3d", "", -inf, inf,
            "the model: 3D, or a 2D section in the plane z = 0: \"axisymmetric\" about the y "
            "axis (r = x, z = y; the eye's meridian section, or a file mesh; results for the "
            "whole body of revolution), \"plane\" strain (a file mesh; results per mm of "
            "thickness)"},
           s.dimension,
           {{"3d", section::Dimension::three},
            {"axisymmetric", section::Dimension::axisymmetric},
            {"plane", section::Dimension::plane}});
  v.path({"mesh.file", "", "", -inf, inf,
          "external mesh (.msh, or a .geo that gmsh meshes), relative to the scene file; its "
          "physical groups map to materials and boundaries",
          on_file},
         s.file);
  v.real({"mesh.size_max", "0.0", "mm", 0, 1e3,
          "file: largest element when nct meshes a .geo (0: as the .geo says)", on_file},
         s.size_max);
  v.options({"mesh.parameters", "{}", "", -inf, inf,
             "file: numbers for a .geo's constants, name = value, each declared there as "
             "DefineConstant[name = {default, Name \"Parameters/name\"}] (e.g. its element sizes)",
             on_file},
            s.parameters);
  visit(v, s.refinement);
  visit(v, s.geometry);
  auto& b = s.boundary;
  v.strings({"boundary.fixed", "[]", "", -inf, inf, "file: facet groups clamped (u = 0)", on_file},
            b.fixed);
  v.strings({"boundary.symmetry", "[]", "", -inf, inf,
             "file: facet groups on axis-aligned symmetry planes (u . n = 0; in the fluid: slip, "
             "and the mesh slides along them)",
             on_file},
            b.symmetry);
  v.strings({"boundary.axis", "[]", "", -inf, inf,
             "file, axisymmetric: facet groups on the axis r = 0 (u_r = 0); every boundary the "
             "section has on the axis must be named here",
             on_file},
            b.axis);
  v.strings({"boundary.cavity_wall", "[]", "", -inf, inf,
             "file: facet groups bounding the fluid cavity (IOP acts here)", on_file},
            b.cavity_wall);
  v.strings({"boundary.humor_open", "[]", "", -inf, inf,
             "file: facet groups of the humor (cavity.humor_groups) where it is open at the "
             "cavity's pressure, p = IOP: an opening to a far field; with cavity.model = "
             "\"constant_pressure\" (a closed humor holds its volume instead)",
             "mesh.source=file,cavity.humor_inertia=flow"},
            b.humor_open);
  v.strings({"boundary.press", "[]", "", -inf, inf,
             "file: facet groups the press (press.pressure) and a prescribed puff act on", on_file},
            b.press);
  v.strings({"boundary.inlet", "[]", "", -inf, inf,
             "file, fsi: fluid facet groups where the velocity is inlet.* (a profile across the "
             "section times a ramp in time)",
             on_file},
            b.inlet);
  v.strings({"boundary.outlet", "[]", "", -inf, inf,
             "file, fsi: fluid facet groups with the natural outflow condition sigma n = 0 and "
             "backflow stabilisation (air.backflow)",
             on_file},
            b.outlet);
  v.strings({"boundary.wall", "[]", "", -inf, inf,
             "file, fsi: fluid facet groups of rigid no-slip walls (u = 0); the fluid's force on "
             "them is its consistent reaction",
             on_file},
            b.wall);
  v.strings({"boundary.interface", "[]", "", -inf, inf,
             "file, fsi: the fluid-solid interface's facet groups; none: the faces between "
             "fluid and solid cells, found from the volume groups (the group 'interface')",
             on_file},
            b.interface);
}

namespace eye
{

void visit(scene::Visitor& v, Refinement& r)
{
  v.integer({"mesh.layers", "5", "", 1, 12, "eye: elements through the wall thickness", on_eye},
            r.layers);
  v.real({"mesh.size_cornea", "0.5", "mm", 0.01, 5, "eye: in-plane element size in the cornea",
          on_eye},
         r.size_cornea);
  v.real({"mesh.size_limbus", "0.5", "mm", 0.01, 5, "eye: in-plane element size in the limbus",
          on_eye},
         r.size_limbus);
  v.real({"mesh.size_sclera", "1.5", "mm", 0.01, 10, "eye: in-plane element size in the sclera",
          on_eye},
         r.size_sclera);
  v.real({"mesh.size_lens", "0.8", "mm", 0.05, 5,
          "eye: in-plane element size in the lens and zonule", on_internal},
         r.size_lens);
  v.real({"mesh.size_humor", "0.5", "mm", 0.01, 10,
          "eye: largest element of the humor's mesh (cavity.humor_inertia = \"flow\"), graded "
          "from the wall's spacing",
          "mesh.source=eye,cavity.humor_inertia=flow|navier_stokes"},
         r.size_humor);
}

void visit(scene::Visitor& v, Geometry& g)
{
  v.real({"geometry.cornea_anterior_radius", "7.8", "mm", 5, 12,
          "radius of the anterior corneal sphere", on_eye},
         g.cornea_anterior_radius);
  v.real({"geometry.cornea_posterior_radius", "6.5", "mm", 4, 12,
          "radius of the posterior corneal sphere", on_eye},
         g.cornea_posterior_radius);
  v.real({"geometry.cornea_central_thickness", "0.55", "mm", 0.2, 1.5,
          "central corneal thickness", on_eye},
         g.cornea_central_thickness);
  v.real({"geometry.limbus_diameter", "11.7", "mm", 8, 14,
          "diameter of the anterior cornea-sclera junction", on_eye},
         g.limbus_diameter);
  v.real({"geometry.limbus_width", "1.0", "mm", 0.2, 4,
          "meridional width of the limbus band, centred on the junction", on_eye},
         g.limbus_width);
  v.real({"geometry.sclera_outer_radius", "12.0", "mm", 9, 15,
          "outer radius of the scleral sphere (centred at the origin)", on_eye},
         g.sclera_outer_radius);
  v.real({"geometry.sclera_thickness", "0.8", "mm", 0.3, 2, "scleral thickness", on_eye},
         g.sclera_thickness);
  v.real({"geometry.cut_y", "-4.0", "mm", -11, 8,
          "posterior cut plane y = cut_y (fixed); the cavity is closed there", on_eye},
         g.cut_y);
  v.boolean({"geometry.internal_structures", "false", "", -inf, inf,
             "lens (cortex, nucleus), ciliary zonule and vitreous membrane; they split the cavity "
             "into aqueous and vitreous",
             on_eye},
            g.internal_structures);
  v.real({"geometry.anterior_chamber_depth", "3.0", "mm", 1, 6,
          "posterior corneal apex to the anterior lens pole", on_internal},
         g.anterior_chamber_depth);
  v.real({"geometry.lens_thickness", "4.0", "mm", 2, 6, "lens thickness on the axis", on_internal},
         g.lens_thickness);
  v.real({"geometry.lens_diameter", "9.5", "mm", 6, 11, "lens diameter at its equator",
          on_internal},
         g.lens_diameter);
  v.real({"geometry.lens_anterior_radius", "10.0", "mm", 5, 20,
          "radius of the anterior lens surface", on_internal},
         g.lens_anterior_radius);
  v.real({"geometry.lens_posterior_radius", "6.0", "mm", 4, 20,
          "radius of the posterior lens surface", on_internal},
         g.lens_posterior_radius);
  v.real({"geometry.lens_nucleus_fraction", "0.6", "", 0.1, 0.9,
          "the nucleus spans this fraction of the lens radius (and the middle layers)", on_internal},
         g.lens_nucleus_fraction);
  v.real({"geometry.ciliary_offset", "2.0", "mm", 0.2, 6,
          "arc length on the inner sclera from the posterior cornea-sclera junction back to the "
          "zonule's attachment ring",
          on_internal},
         g.ciliary_offset);
}

} // namespace eye
} // namespace nct
