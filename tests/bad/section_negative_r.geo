// A square across the axis x = 0: not an axisymmetric section.
SetFactory("OpenCASCADE");
Rectangle(1) = {-1, 0, 0, 2, 1};
Physical Surface("tissue") = {1};
Physical Curve("sides") = {1, 2, 3, 4};
