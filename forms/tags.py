"""The integration tags: which integrals of the forms a cell or facet takes part in.

A form integrates over dx(tag) or ds(tag); the C++ driver marks each cell
and facet with these tags (cpp/solid/problem.cpp, cpp/air/problem.cpp,
cpp/mesh_motion/problem.cpp). This file is their one owner: the build
writes them into the C++ header form_tags.h (`python3 tags.py <header>`),
and tests/test_form_tags.cpp checks that every compiled form integrates
over these tags and no others.
"""
import sys

# forms/solid.py: a cell's material law (cpp/solid/material.h, solid::Law)
HGO = 1
NEO_HOOKEAN = 2
SAINT_VENANT_KIRCHHOFF = 3
COMPRESSIBLE_NEO_HOOKEAN = 4
# forms/solid.py, forms/humor_inertia.py: a facet's load
CAVITY_1_WALL = 1
PRESS = 2
CAVITY_2_WALL = 3
SUPPORT = 4
# forms/air.py, forms/air_ale.py: the air's facets with an integral
OUTLET = 1
INTERFACE = 2
# forms/mesh_motion.py: the cells whose mesh moves
MOVING = 1
# forms/humor_flow.py: the humor's facets on the solid's cut (its lid)
HUMOR_LID = 1

LAWS = ["HGO", "NEO_HOOKEAN", "SAINT_VENANT_KIRCHHOFF", "COMPRESSIBLE_NEO_HOOKEAN"]
SOLID_LOADS = ["CAVITY_1_WALL", "PRESS", "CAVITY_2_WALL", "SUPPORT"]
AIR_FACETS = ["OUTLET", "INTERFACE"]
MESH_MOTION_CELLS = ["MOVING"]
HUMOR_FACETS = ["HUMOR_LID"]


def header():
    """The C++ header: each tag as nct::forms::tags::<name> (lower case)."""
    lines = ["// Generated from forms/tags.py by the build: do not edit.",
             "#pragma once", "#include <cstdint>", "",
             "namespace nct::forms::tags", "{"]
    for group in (LAWS, SOLID_LOADS, AIR_FACETS, MESH_MOTION_CELLS, HUMOR_FACETS):
        for name in group:
            lines.append(f"constexpr std::int32_t {name.lower()} = {globals()[name]};")
    lines += ["} // namespace nct::forms::tags", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    with open(sys.argv[1], "w") as f:
        f.write(header())
