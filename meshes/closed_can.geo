// A closed can as an axisymmetric section about the y axis: the rectangle
// [0, 2] x [0, 3] without the cavity [0, 1] x [1, 2], "wall"; curves
// "axis" (x = 0), "bottom" (y = 0), "cavity" (the cavity's sides off the
// axis) and "outer" (x = 2 and y = 3). As a body: the cylinder of radius
// 2 and height 3 (volume 12 pi) holding a closed cylindrical cavity of
// radius 1 and height 1 (volume pi). Straight sides: the meshed cavity is
// the exact one.
SetFactory("OpenCASCADE");
DefineConstant[h = {0.25, Name "Parameters/h"}];
Rectangle(1) = {0, 0, 0, 2, 3};
Rectangle(2) = {0, 1, 0, 1, 1};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
e = 1e-6;
Physical Surface("wall") = {3};
Physical Curve("axis") = Curve In BoundingBox{-e, -e, -e, e, 3 + e, e};
Physical Curve("bottom") = Curve In BoundingBox{-e, -e, -e, 2 + e, e, e};
Physical Curve("cavity") = Curve In BoundingBox{-e, 1 - e, -e, 1 + e, 2 + e, e};
Physical Curve("cavity") -= Curve In BoundingBox{-e, -e, -e, e, 3 + e, e};
Physical Curve("outer") = Curve In BoundingBox{-e, -e, -e, 2 + e, 3 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, 1 - e, -e, 1 + e, 2 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, e, 3 + e, e};
Physical Curve("outer") -= Curve In BoundingBox{-e, -e, -e, 2 + e, e, e};
Mesh.CharacteristicLengthMax = h;
