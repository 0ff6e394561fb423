// A hollow ball (radii a_i, a) inside a fluid-filled sphere (radius b)
// as an axisymmetric section about the y axis: surfaces "ball" and
// "humor" (the fluid between the ball and the container); curves "axis"
// (x = 0), "cavity" (the ball's outer surface, wetted), "container" (the
// fixed outer sphere), "void_top" and "void_bottom" (the ball's inner
// surface above and below y = 0). Built-in kernel: every arc is a
// curve of its own, so the groups are exact.
DefineConstant[h = {0.05, Name "Parameters/h"}];
DefineConstant[a_i = {0.5, Name "Parameters/a_i"}];
DefineConstant[a = {1.0, Name "Parameters/a"}];
DefineConstant[b = {2.0, Name "Parameters/b"}];
Point(1) = {0, 0, 0, h};
Point(2) = {0, -b, 0, h};
Point(3) = {0, -a, 0, h};
Point(4) = {0, -a_i, 0, h};
Point(5) = {0, a_i, 0, h};
Point(6) = {0, a, 0, h};
Point(7) = {0, b, 0, h};
Point(8) = {a_i, 0, 0, h};
Point(9) = {a, 0, 0, h};
Point(10) = {b, 0, 0, h};
Circle(1) = {4, 1, 8};
Circle(2) = {8, 1, 5};
Circle(3) = {3, 1, 9};
Circle(4) = {9, 1, 6};
Circle(5) = {2, 1, 10};
Circle(6) = {10, 1, 7};
Line(7) = {2, 3};
Line(8) = {3, 4};
Line(9) = {5, 6};
Line(10) = {6, 7};
Curve Loop(1) = {8, 1, 2, 9, -4, -3};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 3, 4, 10, -6, -5};
Plane Surface(2) = {2};
Physical Surface("ball") = {1};
Physical Surface("humor") = {2};
Physical Curve("axis") = {7, 8, 9, 10};
Physical Curve("cavity") = {3, 4};
Physical Curve("container") = {5, 6};
Physical Curve("void_top") = {2};
Physical Curve("void_bottom") = {1};
Mesh.CharacteristicLengthMax = h;
