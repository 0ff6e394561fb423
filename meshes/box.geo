// Unit cube for material tests: one volume "tissue" and its six faces,
// named by the plane they lie on (x0: x = 0, x1: x = 1, ...).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
e = 1e-6;
Physical Volume("tissue") = {1};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 1 + e};
Physical Surface("x1") = Surface In BoundingBox{1 - e, -e, -e, 1 + e, 1 + e, 1 + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, -e, 1 + e, e, 1 + e};
Physical Surface("y1") = Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 1 + e, 1 + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Surface("z1") = Surface In BoundingBox{-e, -e, 1 - e, 1 + e, 1 + e, 1 + e};
Mesh.CharacteristicLengthMax = 0.5;
