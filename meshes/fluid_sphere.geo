// A thin spherical shell (mid-surface radius a, thickness t) filled with
// fluid, as a quarter of its axisymmetric section about the y axis (the
// mirror plane y = 0): surfaces "shell" (t / 2 each side of a, n_t
// elements through the thickness, n_a along the quarter arc) and "humor"
// (the fluid inside); curves "axis" (x = 0), "equator" (y = 0), "cavity"
// (the shell's inner surface, wetted) and "outer" (its outer surface).
DefineConstant[a = {25.0, Name "Parameters/a"}];
DefineConstant[t = {0.5, Name "Parameters/t"}];
DefineConstant[n_a = {80, Name "Parameters/n_a"}];
DefineConstant[n_t = {2, Name "Parameters/n_t"}];
DefineConstant[h_core = {3.0, Name "Parameters/h_core"}];
r_i = a - t / 2;
r_o = a + t / 2;
h_wall = 1.5707963267948966 * r_i / n_a;
Point(1) = {0, 0, 0, h_core};
Point(2) = {r_i, 0, 0, h_wall};
Point(3) = {r_o, 0, 0, h_wall};
Point(4) = {0, r_i, 0, h_wall};
Point(5) = {0, r_o, 0, h_wall};
Circle(1) = {2, 1, 4};
Circle(2) = {3, 1, 5};
Line(3) = {1, 4};
Line(4) = {4, 5};
Line(5) = {1, 2};
Line(6) = {2, 3};
Curve Loop(1) = {6, 2, -4, -1};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 1, -3};
Plane Surface(2) = {2};
Transfinite Curve{1, 2} = n_a + 1;
Transfinite Curve{4, 6} = n_t + 1;
Transfinite Surface{1};
Physical Surface("shell") = {1};
Physical Surface("humor") = {2};
Physical Curve("axis") = {3, 4};
Physical Curve("equator") = {5, 6};
Physical Curve("cavity") = {1};
Physical Curve("outer") = {2};
