// The air domain of the puff: the nozzle and the air between it and the
// eye, meshed in the same gmsh model as the eye (one conforming mesh).
#pragma once

namespace nct::air
{

/// Shape and mesh sizes of the air domain (docs/physics.md sections 4 and 8).
/// Lengths in mm, in the eye's frame (optical axis +y, towards the nozzle).
///
/// The domain is the quarter (x >= 0, z >= 0) of a cylinder about the
/// optical axis, of radius `radius`, from the eye's cut plane y = cut_y up
/// to the device face y = apex_y + nozzle_distance + nozzle_length, minus
/// the eye and the nozzle. The nozzle is a tube (inner diameter
/// nozzle_diameter, outer nozzle_outer_diameter) from its exit,
/// nozzle_distance above the corneal apex, up to the device face, where its
/// bore is the inlet. Its keys and defaults: [air] (cpp/settings/air.cpp).
struct Domain
{
  double radius;
  double nozzle_diameter;
  double nozzle_outer_diameter;
  double nozzle_distance; ///< nozzle exit to corneal apex, along the axis
  double nozzle_length;    ///< nozzle exit to inlet (the device face)
  double size_nozzle; ///< element size in the nozzle's bore and at its exit
  double size_jet;  ///< element size within jet_radius of the axis, inlet to apex
  double jet_radius; ///< radius of the finely meshed core of the jet
  double size_far;   ///< largest element size, towards the far boundary
  double size_gradation; ///< growth of the element size per mm away from the core [mm/mm]
};

/// Physical tags of the air: its volume, and its boundary groups. The eye's
/// anterior surfaces ("anterior_cornea", "anterior_sclera") bound it too.
enum class Group
{
  volume = 8,        ///< "air"
  inlet = 11,        ///< "inlet": the nozzle's bore at the device face
  outlet = 12,       ///< "outlet": device face, far cylinder, bottom plane
  nozzle = 13,       ///< "nozzle": the nozzle's walls
  symmetry_x = 14,   ///< "air_symmetry_x": air on x = 0
  symmetry_z = 15,   ///< "air_symmetry_z": air on z = 0
  axis = 16          ///< "air_axis": a section's air on the axis r = 0
};

/// Throws std::invalid_argument naming the air.* key of an impossible
/// shape or size (cheap: no meshing). `eye_radius`: the eye's largest
/// distance from the axis (0 without the eye).
void validate(const Domain& d, double apex_y, double bottom_y, double eye_radius);

/// Mesh the air domain into the current gmsh model (rank 0, after
/// gmsh::initialize). `around_eye`: the current model is the meshed eye
/// (eye::build), whose anterior surfaces' triangles become the air's wall,
/// node for node, whose cut plane is y = bottom_y and which lies within
/// eye_radius of the axis. Otherwise a new
/// model "air" holds the air alone (the free jet), the eye's place left
/// empty; apex_y is where the apex would be. Throws std::invalid_argument
/// naming the air.* key of an impossible shape, std::runtime_error if gmsh
/// fails.
void build(const Domain& d, double apex_y, double bottom_y, double eye_radius, bool around_eye);

/// The same in the meridian plane (r = x >= 0, y; an axisymmetric
/// section): the 3D domain's plane z = 0, meshed in triangles into the
/// current gmsh model, around the eye's section (eye::build_section),
/// whose anterior segments become the air's wall node for node, or alone.
/// Surface "air" (tag 8); curves "inlet", "outlet", "nozzle", "air_axis"
/// (Group). Throws as build().
void build_section(const Domain& d, double apex_y, double bottom_y, double eye_radius,
                   bool around_eye);

} // namespace nct::air
