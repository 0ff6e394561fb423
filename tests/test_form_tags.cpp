// The integration tags: the compiled forms integrate over the tags of
// forms/tags.py (the C++ side's form_tags.h) and no others, so that a
// form written with a number of its own, or a tag the driver never marks,
// fails here instead of integrating over nothing.
#include <set>
#include <gtest/gtest.h>

#include "air_ale_p1_full.h"
#include "air_p1_full.h"
#include "form_tags.h"
#include "humor_flow_p2_full_axisymmetric.h"
#include "humor_inertia_p1_full.h"
#include "mesh_motion_p1_full_plane.h"
#include "solid/material.h"
#include "solid_p1_full.h"
#include "solid_p1_full_axisymmetric.h"
#include "solid_p2_full_mixed_plane.h"

namespace
{
namespace tags = nct::forms::tags;

/// The subdomain ids a form's integrals of one type are over (-1: all).
std::set<int> ids(const ufcx_form* form, ufcx_integral_type type)
{
  const int* begin = form->integral_ids(type);
  return {begin, begin + form->num_integrals(type)};
}

constexpr int everywhere = -1;
} // namespace

TEST(FormTags, SolidCellsByLawFacetsByLoad)
{
  const std::set<int> laws = {tags::hgo, tags::neo_hookean, tags::saint_venant_kirchhoff,
                              tags::compressible_neo_hookean};
  const std::set<int> loads = {tags::cavity_1_wall, tags::press, tags::cavity_2_wall,
                               tags::support};
  for (const ufcx_form* f :
       {form_solid_p1_full_R, form_solid_p1_full_axisymmetric_R, form_solid_p2_full_mixed_plane_R})
  {
    EXPECT_EQ(ids(f, cell), laws);
    EXPECT_EQ(ids(f, exterior_facet), loads);
    EXPECT_TRUE(ids(f, interior_facet).empty());
  }
  // In dynamics the inertia (its density per cell) is over every cell.
  auto laws_and_inertia = laws;
  laws_and_inertia.insert(everywhere);
  EXPECT_EQ(ids(form_solid_p1_full_J_dynamic, cell), laws_and_inertia);
  EXPECT_EQ(ids(form_solid_p1_full_J_dynamic, exterior_facet), loads);
  EXPECT_EQ(ids(form_solid_p1_full_volume_1, exterior_facet),
            (std::set<int>{tags::cavity_1_wall, tags::support}));
  EXPECT_EQ(ids(form_solid_p1_full_volume_2, exterior_facet),
            (std::set<int>{tags::cavity_2_wall, tags::support}));
  // The material laws' values are the cell tags.
  EXPECT_EQ(static_cast<int>(nct::solid::Law::hgo), tags::hgo);
  EXPECT_EQ(static_cast<int>(nct::solid::Law::compressible_neo_hookean),
            tags::compressible_neo_hookean);
  EXPECT_EQ(laws.count(static_cast<int>(nct::solid::Law::fluid)), 0u);
}

TEST(FormTags, HumorInertiaOnTheCavityWalls)
{
  EXPECT_EQ(ids(form_humor_inertia_p1_full_moment, exterior_facet),
            (std::set<int>{tags::cavity_1_wall, tags::cavity_2_wall, tags::support}));
}

TEST(FormTags, HumorFlowOnTheWallsTheCutAndTheLid)
{
  const auto* k = form_humor_flow_p2_full_axisymmetric_load;
  EXPECT_EQ(ids(k, exterior_facet), (std::set<int>{tags::cavity_1_wall, tags::cavity_2_wall}));
  EXPECT_EQ(ids(form_humor_flow_p2_full_axisymmetric_flux_1, exterior_facet),
            std::set<int>{tags::cavity_1_wall});
  EXPECT_EQ(ids(form_humor_flow_p2_full_axisymmetric_flux_2, exterior_facet),
            std::set<int>{tags::cavity_2_wall});
  EXPECT_EQ(ids(form_humor_flow_p2_full_axisymmetric_cut_normal, exterior_facet),
            std::set<int>{tags::support});
  // On the humor's mesh: every cell, and its lid.
  EXPECT_EQ(ids(form_humor_flow_p2_full_axisymmetric_laplace, cell), std::set<int>{everywhere});
  EXPECT_EQ(ids(form_humor_flow_p2_full_axisymmetric_lid_area, exterior_facet),
            std::set<int>{tags::humor_lid});
}

TEST(FormTags, AirOutletAndInterface)
{
  for (const ufcx_form* f : {form_air_p1_full_R, form_air_ale_p1_full_R})
  {
    EXPECT_EQ(ids(f, cell), std::set<int>{everywhere});
    EXPECT_EQ(ids(f, exterior_facet), std::set<int>{tags::outlet});
  }
  for (const ufcx_form* f : {form_air_ale_p1_full_force_x, form_air_ale_p1_full_traction_power})
    EXPECT_EQ(ids(f, exterior_facet), std::set<int>{tags::interface});
}

TEST(FormTags, MeshMotionOnTheMovingCells)
{
  for (const ufcx_form* f :
       {form_mesh_motion_p1_full_plane_R_harmonic, form_mesh_motion_p1_full_plane_R_elastic})
    EXPECT_EQ(ids(f, cell), std::set<int>{tags::moving});
}
