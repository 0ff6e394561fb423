// Quarter of an annulus in the plane z = 0, inner radius A, outer radius
// B: "wall" surface; curves "inner" (the cavity wall), "outer", "x0" (on
// x = 0) and "y0" (on y = 0). As an axisymmetric section about the y axis
// it is half of a thick-walled sphere ("x0" its axis, "y0" a mirror
// plane); in plane strain, a quarter of a thick-walled cylinder.
SetFactory("OpenCASCADE");
A = 1.0;
B = 1.5;
Disk(1) = {0, 0, 0, B};
Disk(2) = {0, 0, 0, A};
Rectangle(3) = {0, 0, 0, 2 * B, 2 * B};
BooleanDifference(4) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
BooleanIntersection(5) = { Surface{4}; Delete; }{ Surface{3}; Delete; };
e = 1e-6;
Physical Surface("wall") = {5};
Physical Curve("x0") = Curve In BoundingBox{-e, -e, -e, e, B + e, e};
Physical Curve("y0") = Curve In BoundingBox{-e, -e, -e, B + e, e, e};
Physical Curve("inner") = Curve In BoundingBox{-e, -e, -e, A + e, A + e, e};
Physical Curve("inner") -= Curve In BoundingBox{-e, -e, -e, e, B + e, e};
Physical Curve("inner") -= Curve In BoundingBox{-e, -e, -e, B + e, e, e};
Physical Curve("outer") = Curve In BoundingBox{-e, -e, -e, B + e, B + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, A + e, A + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, e, B + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, B + e, e, e};
Mesh.CharacteristicLengthMax = 0.12;
