// A circular plate (radius a, thickness t) clamped at its rim, on a fluid
// half-space cut off at the hemisphere of radius R, as an axisymmetric
// section about the y axis: surfaces "plate" (n_a elements along its
// radius, n_t through its thickness, structured) and "humor" (the fluid
// below it, y < 0); curves "axis" (x = 0), "cavity" (the plate's wetted
// face), "rim" (x = a), "top" (its dry face), "baffle" (the rigid plane y
// = 0 beyond the rim) and "far" (the hemisphere).
DefineConstant[a = {5.0, Name "Parameters/a"}];
DefineConstant[t = {0.5, Name "Parameters/t"}];
DefineConstant[R = {20.0, Name "Parameters/R"}];
DefineConstant[n_a = {20, Name "Parameters/n_a"}];
DefineConstant[n_t = {2, Name "Parameters/n_t"}];
h_plate = a / n_a;
h_far = R / 8;
Point(1) = {0, 0, 0, h_plate};
Point(2) = {a, 0, 0, h_plate};
Point(3) = {a, t, 0, h_plate};
Point(4) = {0, t, 0, h_plate};
Point(5) = {R, 0, 0, h_far};
Point(6) = {0, -R, 0, h_far};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {2, 5};
Circle(6) = {5, 1, 6};
Line(7) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {1, 5, 6, 7};
Plane Surface(2) = {2};
Transfinite Curve{1, 3} = n_a + 1;
Transfinite Curve{2, 4} = n_t + 1;
Transfinite Surface{1};
Physical Surface("plate") = {1};
Physical Surface("humor") = {2};
Physical Curve("axis") = {4, 7};
Physical Curve("cavity") = {1};
Physical Curve("rim") = {2};
Physical Curve("top") = {3};
Physical Curve("baffle") = {5};
Physical Curve("far") = {6};
