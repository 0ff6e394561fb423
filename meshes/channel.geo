// A plane channel as a slab (pseudo-2D), in mm: [0, L] x [0, H] x [0,
// depth], for the fluid alone (tests/scenes/channel_flow.toml).
// Groups: volume "fluid"; surfaces "inlet" (x = 0), "outlet" (x = L),
// "walls_upstream" and "walls_downstream" (y = 0 and y = H, for x below
// and above L / 2), "faces" (z = 0 and z = depth, symmetry planes).
SetFactory("OpenCASCADE");
DefineConstant[h = {1.0, Name "Parameters/h"}, L = {40.0, Name "Parameters/L"},
               H = {10.0, Name "Parameters/H"}, depth = {2.0, Name "Parameters/depth"}];
Rectangle(1) = {0, 0, 0, L / 2, H};
Rectangle(2) = {L / 2, 0, 0, L / 2, H};
BooleanFragments{ Surface{1, 2}; Delete; }{}
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Extrude {0, 0, depth} { Surface{:}; Layers{1}; }
e = 1e-6;
Physical Volume("fluid") = {Volume{:}};
Physical Surface("inlet") = {Surface In BoundingBox{-e, -e, -e, e, H + e, depth + e}};
Physical Surface("outlet") = {Surface In BoundingBox{L - e, -e, -e, L + e, H + e, depth + e}};
Physical Surface("walls_upstream") = {Surface In BoundingBox{-e, -e, -e, L / 2 + e, e, depth + e},
                                      Surface In BoundingBox{-e, H - e, -e, L / 2 + e, H + e, depth + e}};
Physical Surface("walls_downstream") = {Surface In BoundingBox{L / 2 - e, -e, -e, L + e, e, depth + e},
                                        Surface In BoundingBox{L / 2 - e, H - e, -e, L + e, H + e, depth + e}};
Physical Surface("faces") = {Surface In BoundingBox{-e, -e, -e, L + e, H + e, e},
                             Surface In BoundingBox{-e, -e, depth - e, L + e, H + e, depth + e}};
