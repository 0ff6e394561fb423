// Slender cantilever for the locking test (tests/test_robust.cpp): 10 mm
// long (x), 1 x 1 mm section; clamped on x0, loaded on the top face y1.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 10, 1, 1};
e = 1e-6;
Physical Volume("beam") = {1};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 1 + e};
Physical Surface("y1") = Surface In BoundingBox{-e, 1 - e, -e, 10 + e, 1 + e, 1 + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, 10 + e, 1 + e, e};
Mesh.CharacteristicLengthMax = 0.5;
