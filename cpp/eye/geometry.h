// The idealised eye: a parametric, layered gmsh model of the quarter eye
// and of its meridian section. The shape and the fibres: shape.cpp; the
// quarter eye's mesh: mesh.cpp; the section's: section_mesh.cpp.
#pragma once

#include <array>
#include <string>

namespace nct::eye
{

/// Shape of the idealised eye (docs/physics.md section 4). Lengths in mm.
///
/// Frame: origin at the centre of the scleral sphere, optical axis +y
/// (anterior, towards the nozzle), x nasal-temporal, z superior-inferior.
/// The model is the quarter x >= 0, z >= 0, cut by the plane y = cut_y.
/// Its keys and defaults: [geometry] (cpp/settings/mesh.cpp;
/// scene::defaults<Geometry>()).
struct Geometry
{
  double cornea_anterior_radius;   ///< Ra
  double cornea_posterior_radius;  ///< Rp
  double cornea_central_thickness; ///< tc
  double limbus_diameter;  ///< diameter of the anterior cornea-sclera junction
  double limbus_width;      ///< meridional width of the limbus band
  double sclera_outer_radius; ///< Rs
  double sclera_thickness;     ///< ts
  double cut_y;               ///< posterior cut plane y = cut_y

  /// Internal structures: the "diaphragm" of lens, zonule band and vitreous
  /// membrane, a second layered body splitting the cavity into the aqueous
  /// (in front) and vitreous (behind) chambers. Off: the eye is as without
  /// these keys (one "cavity_wall") and the keys below are not validated.
  bool internal_structures;
  double anterior_chamber_depth; ///< posterior corneal apex to anterior lens pole, on the axis
  double lens_thickness;         ///< anterior to posterior lens pole, on the axis
  double lens_diameter;          ///< diameter of the lens equator
  double lens_anterior_radius;  ///< anterior lens sphere (centre below the anterior pole)
  double lens_posterior_radius;  ///< posterior lens sphere (centre above the posterior pole)
  double lens_nucleus_fraction;  ///< nucleus: chart radius < this times the lens radius (middle layers)
  double ciliary_offset; ///< arc length along the inner scleral sphere from the posterior
                               ///< cornea-sclera junction, backwards, to the zonule ring
};

/// Mesh refinement of the idealised eye ([mesh], cpp/settings/mesh.cpp).
struct Refinement
{
  int layers;             ///< elements through the thickness
  double size_cornea;   ///< in-plane element size in the cornea [mm]
  double size_limbus;   ///< in-plane element size in the limbus [mm]
  double size_sclera;   ///< in-plane element size in the sclera [mm]
  double size_lens;     ///< in-plane element size in the lens (internal structures) [mm]
  double size_humor;    ///< largest element of the humor's mesh (its flow) [mm]
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
  /// Internal structures only (else 0), whole eye [mm^3]: the chamber
  /// between the inner surface in front of the zonule ring and the
  /// diaphragm's anterior surface, and the one between the inner surface
  /// behind the ring, the diaphragm's posterior surface and the cut plane.
  /// aqueous + vitreous + diaphragm solid = cavity_volume.
  double aqueous_volume;
  double vitreous_volume;
};

/// Derived points and the analytic cavity volume; throws
/// std::invalid_argument naming the geometry key when the shape is
/// impossible (e.g. the posterior cornea misses the inner sclera, or the
/// lens does not fit the cavity).
///
/// Internal structures (axisymmetric, meridian (r, y)): lens poles on the
/// axis at y = apex_y - cornea_central_thickness - anterior_chamber_depth
/// and lens_thickness below; anterior/posterior surfaces spheres through
/// the poles, cut at r = lens_diameter / 2 (rim thickness must be > 0).
/// The zonule band runs from the two rim points straight to one ring point
/// R on the inner scleral sphere (ciliary_offset behind the posterior
/// junction), tapering to a cusp there. The lens and band must lie inside
/// the cavity and R above the cut plane.
Derived derive(const Geometry& g);

/// Parts of the eye; the values are the volume physical tags. The last
/// four exist only with Geometry::internal_structures.
enum class Part
{
  cornea = 1,
  limbus = 2,
  sclera = 3,
  lens_cortex = 4,
  lens_nucleus = 5,
  zonule = 6,
  vitreous_membrane = 7
};

/// Fibre directions of a point X in the reference configuration.
/// Cornea: two families, e_x and e_z projected onto the tangent plane of
/// the anterior corneal sphere at X and normalised. Limbus: one
/// circumferential family e_phi; the second is zero. Sclera and the
/// internal structures (lens, zonule, vitreous membrane): both zero.
/// Cheap and unvalidated: g must be one that derive() accepts.
std::array<std::array<double, 3>, 2> fibres(const Geometry& g, Part part,
                                            const std::array<double, 3>& X);

/// Build the meshed quarter eye as the current gmsh model (call on one
/// rank, after gmsh::initialize). Volumes: physical groups "cornea",
/// "limbus", "sclera" (tags 1, 2, 3 = Part). Surfaces: "anterior_cornea",
/// "anterior_sclera" (outer surface of limbus and sclera), "cavity_wall"
/// (the whole inner surface), "symmetry_x" (on x = 0), "symmetry_z"
/// (on z = 0), "fixed" (the cut face y = cut_y); surface tags 1..6 in that
/// order, triangles oriented out of the solid.
///
/// With Geometry::internal_structures the diaphragm is a second layered
/// body (same layers) sharing the sclera's inner nodes on the zonule ring
/// (a conforming line contact). Volumes add "lens_cortex", "lens_nucleus",
/// "zonule", "vitreous_membrane" (tags 4..7 = Part); "cavity_wall" (3) is
/// replaced by "aqueous_wall" (tag 7: posterior cornea and limbus, inner
/// sclera in front of the ring, diaphragm's anterior surface) and
/// "vitreous_wall" (tag 8: inner sclera behind the ring, diaphragm's
/// posterior surface); diaphragm faces on x = 0 / z = 0 join symmetry_x /
/// symmetry_z. Lens cells are nucleus for chart radius < nucleus fraction
/// times lens radius and layers k in [floor(N/4), N - floor(N/4)) of N
/// (all layers for N <= 3), else cortex; band cells are vitreous_membrane
/// in the posterior-most layer and zonule otherwise (all zonule for N = 1).
/// Throws std::invalid_argument
/// for an impossible geometry or refinement (naming the scene key,
/// geometry.* or mesh.*), std::runtime_error if gmsh fails or a
/// tetrahedron comes out inverted.
/// With `humor` (without the internal structures) also the humor inside
/// "cavity_wall" down to the cut: volume "humor" (tag 20), conforming to
/// the wall node for node, its faces on the planes in symmetry_x /
/// symmetry_z, on the cut in "humor_lid" (tag 9); graded from the wall's
/// spacing to Refinement::size_humor.
void build(const Geometry& g, const Refinement& r, bool humor = false);

/// Build the eye's meridian section (r = x >= 0, y; an axisymmetric model
/// of the whole eye) as the current gmsh model, meshed as the 3D eye's
/// layered shell: `layers` rows of triangles between the anterior and
/// posterior profiles, the element size along the meridian per part.
/// Surfaces "cornea", "limbus", "sclera" (tags 1, 2, 3 = Part); curves
/// "anterior_cornea", "anterior_sclera", "cavity_wall", "axis" (r = 0),
/// "fixed" (the cut y = cut_y), tags 1, 2, 3, 4, 6. With
/// Geometry::internal_structures also the diaphragm's section (lens cortex
/// and nucleus, zonule, vitreous membrane: surfaces 4 to 7) from the axis
/// to the shell's posterior node at the zonule ring, and "cavity_wall"
/// split into "aqueous_wall" and "vitreous_wall" (curves 7, 8).
/// With `humor` also the humor inside the inner face, down to the cut:
/// surface "humor" (tag 20), conforming to "cavity_wall" node for node, its
/// axis in "axis", its cut in "humor_lid" (curve 9); graded from the
/// wall's spacing to Refinement::size_humor. With the internal structures
/// two chambers: "aqueous_humor" (20) in front of the diaphragm, on
/// "aqueous_wall", and "vitreous_humor" (21) behind it down to the cut, on
/// "vitreous_wall"; apart (each its own node at the zonule ring).
void build_section(const Geometry& g, const Refinement& r, bool humor = false);

} // namespace nct::eye
