// Octant of a ball of radius B with a concentric core of radius A: "core"
// and "shell" volumes (give both the same material for a homogeneous
// ball), the outer spherical face "surface", symmetry planes "x0", "y0",
// "z0". A lens-like compound sphere: a soft core (the nucleus) in a
// stiffer shell (the cortex).
SetFactory("OpenCASCADE");
DefineConstant[A = {0.6, Name "Parameters/A"}];
DefineConstant[h = {0.25, Name "Parameters/h"}];
B = 1.0;
Sphere(1) = {0, 0, 0, B};
Sphere(2) = {0, 0, 0, A};
Box(3) = {0, 0, 0, 2 * B, 2 * B, 2 * B};
BooleanIntersection(4) = { Volume{1}; Delete; }{ Volume{3}; };
BooleanIntersection(5) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
BooleanFragments{ Volume{4}; Delete; }{ Volume{5}; Delete; }
e = 1e-6;
Physical Volume("core") = Volume In BoundingBox{-e, -e, -e, A + e, A + e, A + e};
Physical Volume("shell") = Volume In BoundingBox{-e, -e, -e, B + e, B + e, B + e};
Physical Volume("shell") -= Volume In BoundingBox{-e, -e, -e, A + e, A + e, A + e};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, B + e, B + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, -e, B + e, e, B + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, B + e, B + e, e};
Physical Surface("surface") = Surface In BoundingBox{-e, -e, -e, B + e, B + e, B + e};
Physical Surface("surface") -= Surface In BoundingBox{-e, -e, -e, A + e, A + e, A + e};
Physical Surface("surface") -= Surface In BoundingBox{-e, -e, -e, e, B + e, B + e};
Physical Surface("surface") -= Surface In BoundingBox{-e, -e, -e, B + e, e, B + e};
Physical Surface("surface") -= Surface In BoundingBox{-e, -e, -e, B + e, B + e, e};
Mesh.CharacteristicLengthMax = h;
