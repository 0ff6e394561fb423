// Octant of a thick-walled sphere, inner radius A, outer radius B:
// "shell" volume; "inner" spherical face (the cavity wall); symmetry planes
// "x0", "y0", "z0".
SetFactory("OpenCASCADE");
A = 1.0;
B = 1.5;
Sphere(1) = {0, 0, 0, B};
Sphere(2) = {0, 0, 0, A};
Box(3) = {0, 0, 0, 2 * B, 2 * B, 2 * B};
BooleanDifference(4) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
BooleanIntersection(5) = { Volume{4}; Delete; }{ Volume{3}; Delete; };
e = 1e-6;
Physical Volume("shell") = {5};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, B + e, B + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, -e, B + e, e, B + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, B + e, B + e, e};
Physical Surface("inner") = Surface In BoundingBox{-e, -e, -e, A + e, A + e, A + e};
Mesh.CharacteristicLengthMax = 0.12;
