// The FSI benchmark of Turek & Hron (2006), in mm, in the plane z = 0 (a
// plane section, mesh.dimension = "plane"): the channel [0, 2500] x [0,
// 410], the rigid cylinder of radius 50 about (200, 200), the elastic
// flag [248.99, 600] x [190, 210] clamped along the cylinder's arc (its
// tip A at (600, 200)); meshes/turek-hron.geo is the same as a 3D slab.
// Groups: surfaces "fluid" and "flag"; curves "inlet" (x = 0), "outlet"
// (x = 2500), "walls" (y = 0, 410), "cylinder" (the cylinder in the
// fluid), "clamp" (the flag's arc on the cylinder); the flag's edges in
// the fluid are the interface, found from the surfaces.
// Size: `h` [mm] within 5 mm of the flag and the cylinder, growing to 4 h
// at 100 mm from them, then from 300 mm to `h_far` at 1200 mm.
SetFactory("OpenCASCADE");
DefineConstant[h = {8.0, Name "Parameters/h"}, h_far = {40.0, Name "Parameters/h_far"}];
L = 2500; H = 410; xc = 200; yc = 200; r = 50; lf = 350; tf = 20;
x0 = xc + Sqrt(r^2 - (tf / 2)^2); // where the flag's edges meet the cylinder

Rectangle(1) = {0, 0, 0, L, H};
Disk(2) = {xc, yc, 0, r};
Rectangle(3) = {xc, yc - tf / 2, 0, r + lf, tf};
BooleanDifference(4) = { Surface{3}; Delete; }{ Surface{2}; };      // the flag
BooleanDifference(5) = { Surface{1}; Delete; }{ Surface{2}; Delete; }; // channel - cylinder
BooleanFragments{ Surface{5}; Delete; }{ Surface{4}; Delete; }
e = 1e-3;
flag() = Surface In BoundingBox{x0 - e, yc - tf / 2 - e, -e, xc + r + lf + e, yc + tf / 2 + e, e};
all() = Surface{:};
fluid() = all();
fluid() -= flag();

// Sizes.
near() = Abs(Boundary{ Surface{flag()}; });
near() += Curve In BoundingBox{xc - r - e, yc - r - e, -e, xc + r + e, yc + r + e, e}; // the cylinder
Field[1] = Distance;
Field[1].CurvesList = {near()};
Field[1].NNodesByEdge = 400;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h;
Field[2].SizeMax = 4 * h;
Field[2].DistMin = 5;
Field[2].DistMax = 100;
Field[3] = Threshold;
Field[3].InField = 1;
Field[3].SizeMin = 4 * h;
Field[3].SizeMax = h_far;
Field[3].DistMin = 300;
Field[3].DistMax = 1200;
Field[4] = Min;
Field[4].FieldsList = {2, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Physical Surface("fluid") = {fluid()};
Physical Surface("flag") = {flag()};
Physical Curve("inlet") = Curve In BoundingBox{-e, -e, -e, e, H + e, e};
Physical Curve("outlet") = Curve In BoundingBox{L - e, -e, -e, L + e, H + e, e};
Physical Curve("walls") = {Curve In BoundingBox{-e, -e, -e, L + e, e, e},
                           Curve In BoundingBox{-e, H - e, -e, L + e, H + e, e}};
// The cylinder's arcs in the fluid, and the flag's arc on it.
round() = Curve In BoundingBox{xc - r - e, yc - r - e, -e, xc + r + e, yc + r + e, e};
clamp() = Curve In BoundingBox{x0 - e, yc - tf / 2 - e, -e, xc + r + e, yc + tf / 2 + e, e};
clamp() -= Curve In BoundingBox{x0 - e, yc - tf / 2 - e, -e, xc + r + lf + e, yc - tf / 2 + e, e};
clamp() -= Curve In BoundingBox{x0 - e, yc + tf / 2 - e, -e, xc + r + lf + e, yc + tf / 2 + e, e};
cylinder() = round();
cylinder() -= clamp();
cylinder() -= Curve In BoundingBox{x0 - e, yc - tf / 2 - e, -e, xc + r + lf + e, yc + tf / 2 + e, e};
Physical Curve("cylinder") = {cylinder()};
Physical Curve("clamp") = {clamp()};
