// The idealised eye: a parametric, layered gmsh model of the quarter eye.
#pragma once

#include <array>
#include <string>

namespace nct::eye
{

/// Shape of the idealised eye (design.md section 4). Lengths in mm.
///
/// Frame: origin at the centre of the scleral sphere, optical axis +y
/// (anterior, towards the nozzle), x nasal-temporal, z superior-inferior.
/// The model is the quarter x >= 0, z >= 0, cut by the plane y = cut_y.
struct Geometry
{
  double cornea_anterior_radius = 7.8;   ///< Ra
  double cornea_posterior_radius = 6.5;  ///< Rp
  double cornea_central_thickness = 0.55; ///< tc
  double limbus_diameter = 11.7;  ///< diameter of the anterior cornea-sclera junction
  double limbus_width = 1.0;      ///< meridional width of the limbus band
  double sclera_outer_radius = 12.0; ///< Rs
  double sclera_thickness = 0.8;     ///< ts
  double cut_y = -4.0;               ///< posterior cut plane y = cut_y
};

/// Mesh refinement of the idealised eye.
struct Refinement
{
  int layers = 5;             ///< elements through the thickness
  double size_cornea = 0.5;   ///< in-plane element size in the cornea [mm]
  double size_limbus = 0.5;   ///< in-plane element size in the limbus [mm]
  double size_sclera = 1.5;   ///< in-plane element size in the sclera [mm]
};

/// Points and quantities derived from a Geometry.
struct Derived
{
  double apex_y;                   ///< y of the anterior corneal apex
  double anterior_centre_y;        ///< centre (0, y, 0) of the anterior corneal sphere
  double posterior_centre_y;       ///< centre (0, y, 0) of the posterior corneal sphere
  double junction_anterior_r;      ///< radius of the anterior cornea-sclera junction
  double junction_anterior_y;
  double junction_posterior_r;     ///< radius of the posterior cornea-sclera junction
  double junction_posterior_y;
  double peripheral_thickness;     ///< corneal thickness at the junction, along the anterior normal
  double cavity_volume;            ///< whole-eye analytic volume bounded by the inner surface and the cut plane [mm^3]
};

/// Derived points and the analytic cavity volume; throws
/// std::invalid_argument naming the geometry key when the shape is
/// impossible (e.g. the posterior cornea misses the inner sclera).
Derived derive(const Geometry& g);

/// Parts of the eye; the values are the volume physical tags.
enum class Part { cornea = 1, limbus = 2, sclera = 3 };

/// Fibre directions of a point X in the reference configuration.
/// Cornea: two families, e_x and e_z projected onto the tangent plane of
/// the anterior corneal sphere at X and normalised. Limbus: one
/// circumferential family e_phi; the second is zero. Sclera: both zero.
/// Cheap and unvalidated: g must be one that derive() accepts.
std::array<std::array<double, 3>, 2> fibres(const Geometry& g, Part part,
                                            const std::array<double, 3>& X);

/// Build the meshed quarter eye as the current gmsh model (call on one
/// rank, after gmsh::initialize). Volumes: physical groups "cornea",
/// "limbus", "sclera" (tags 1, 2, 3 = Part). Surfaces: "anterior_cornea",
/// "anterior_sclera" (outer surface of limbus and sclera), "cavity_wall"
/// (the whole inner surface), "symmetry_x" (on x = 0), "symmetry_z"
/// (on z = 0), "fixed" (the cut face y = cut_y); surface tags 1..6 in that
/// order, triangles oriented out of the solid. Throws std::invalid_argument
/// for an impossible geometry or refinement (naming the scene key,
/// geometry.* or mesh.*), std::runtime_error if gmsh fails or a
/// tetrahedron comes out inverted.
void build(const Geometry& g, const Refinement& r);

} // namespace nct::eye
