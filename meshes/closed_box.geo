// A closed box, a quarter of it (mirror planes x = 0 and z = 0): the box
// [0, 2] x [0, 3] x [0, 2] without the cavity [0, 1] x [1, 2] x [0, 1],
// "wall"; faces "x0", "z0" (on the mirror planes), "bottom" (y = 0),
// "cavity" (the cavity's faces off the mirror planes) and "outer" (x = 2,
// y = 3, z = 2). The whole body: a 4 x 3 x 4 box (volume 48) holding a
// closed 2 x 1 x 2 cavity (volume 4).
SetFactory("OpenCASCADE");
DefineConstant[h = {0.5, Name "Parameters/h"}];
Box(1) = {0, 0, 0, 2, 3, 2};
Box(2) = {0, 1, 0, 1, 1, 1};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
e = 1e-6;
Physical Volume("wall") = {3};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, 3 + e, 2 + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, 2 + e, 3 + e, e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 2 + e, e, 2 + e};
Physical Surface("cavity") = Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 2 + e, 1 + e};
Physical Surface("cavity") -= Surface In BoundingBox{-e, -e, -e, e, 3 + e, 2 + e};
Physical Surface("cavity") -= Surface In BoundingBox{-e, -e, -e, 2 + e, 3 + e, e};
Physical Surface("outer") = Surface In BoundingBox{-e, -e, -e, 2 + e, 3 + e, 2 + e};
Physical Surface("outer") -= Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 2 + e, 1 + e};
Physical Surface("outer") -= Surface In BoundingBox{-e, -e, -e, e, 3 + e, 2 + e};
Physical Surface("outer") -= Surface In BoundingBox{-e, -e, -e, 2 + e, 3 + e, e};
Physical Surface("outer") -= Surface In BoundingBox{-e, -e, -e, 2 + e, e, 2 + e};
Mesh.CharacteristicLengthMax = h;
