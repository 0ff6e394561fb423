"""The options a formulation is compiled with: CMake's nct_add_form sets
them in each build's wrapper before it runs the formulation, which imports
the ones it reads (`from options import degree, dimension`).

    degree             the element degree of the displacement (or velocity), 1 or 2
    quadrature_degree  the cell integrals' quadrature degree
    variant            "" or the formulation's variant (solid.py: "mixed")
    dimension          "3d", "axisymmetric" or "plane" (section.py)

Nothing is set here: a formulation run outside its wrapper stops at its import.
"""
degree: int
quadrature_degree: int
variant: str
dimension: str
