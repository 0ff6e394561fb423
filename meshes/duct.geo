// A straight duct in the plane z = 0, along y: [0, R] x [0, L], for the
// fluid alone on a 2D section. Groups: surface "fluid"; curves "inlet"
// (y = 0), "outlet" (y = L), "x0" (x = 0), "wall_upstream" and
// "wall_downstream" (x = R, for y below and above L / 2). As an
// axisymmetric section about the y axis, a pipe of radius R ("x0" its
// axis); in plane strain, half of a channel of width 2 R ("x0" its
// mirror line).
SetFactory("OpenCASCADE");
DefineConstant[h = {1.0, Name "Parameters/h"}, L = {40.0, Name "Parameters/L"},
               R = {5.0, Name "Parameters/R"}];
Rectangle(1) = {0, 0, 0, R, L / 2};
Rectangle(2) = {0, L / 2, 0, R, L / 2};
BooleanFragments{ Surface{1, 2}; Delete; }{}
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
e = 1e-6;
Physical Surface("fluid") = {Surface{:}};
Physical Curve("inlet") = {Curve In BoundingBox{-e, -e, -e, R + e, e, e}};
Physical Curve("outlet") = {Curve In BoundingBox{-e, L - e, -e, R + e, L + e, e}};
Physical Curve("x0") = {Curve In BoundingBox{-e, -e, -e, e, L + e, e}};
Physical Curve("wall_upstream") = {Curve In BoundingBox{R - e, -e, -e, R + e, L / 2 + e, e}};
Physical Curve("wall_downstream") = {Curve In BoundingBox{R - e, L / 2 - e, -e, R + e, L + e, e}};
