// The unit square in the plane z = 0: "tissue" surface; curves "x0",
// "x1", "y0", "y1" on its sides. As an axisymmetric section about the y
// axis, a solid cylinder of radius 1 and length 1 ("x0" its axis).
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
e = 1e-6;
Physical Surface("tissue") = {1};
Physical Curve("x0") = Curve In BoundingBox{-e, -e, -e, e, 1 + e, e};
Physical Curve("x1") = Curve In BoundingBox{1 - e, -e, -e, 1 + e, 1 + e, e};
Physical Curve("y0") = Curve In BoundingBox{-e, -e, -e, 1 + e, e, e};
Physical Curve("y1") = Curve In BoundingBox{-e, 1 - e, -e, 1 + e, 1 + e, e};
Mesh.CharacteristicLengthMax = 0.34;
