// A quarter of a square ring in the plane z = 0: the square [0, 2]^2
// without [0, 1]^2, "wall"; curves "cavity" (the inner square's sides
// x = 1 and y = 1), "outer", "x0" and "y0" (on x = 0 and y = 0). As an
// axisymmetric section about the y axis, half of a closed can whose
// cylindrical cavity (radius 1, height 2) has the volume 2 pi; in plane
// strain, a quarter of a square tube whose hole has the area 4. Straight
// sides: the meshed cavity is the exact one.
SetFactory("OpenCASCADE");
DefineConstant[h = {0.25, Name "Parameters/h"}];
Rectangle(1) = {0, 0, 0, 2, 2};
Rectangle(2) = {0, 0, 0, 1, 1};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
e = 1e-6;
Physical Surface("wall") = {3};
Physical Curve("x0") = Curve In BoundingBox{-e, -e, -e, e, 2 + e, e};
Physical Curve("y0") = Curve In BoundingBox{-e, -e, -e, 2 + e, e, e};
Physical Curve("cavity") = Curve In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Curve("cavity") -= Curve In BoundingBox{-e, -e, -e, e, 2 + e, e};
Physical Curve("cavity") -= Curve In BoundingBox{-e, -e, -e, 2 + e, e, e};
Physical Curve("outer") = Curve In BoundingBox{-e, -e, -e, 2 + e, 2 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, e, 2 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, 2 + e, e, e};
Mesh.CharacteristicLengthMax = h;
