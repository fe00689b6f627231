// The 2D disk of docs/design.md §7 (disk.geo) in quadrilaterals: a
// transfinite O-grid, a square (its corners on the axes) and four blocks to
// the circle, the circle's four arcs those of disk.geo. Physical groups as
// disk.geo's: 1 = lower half of the circle (contact), 2 = upper half, 10 = the disk.
// Mesh size h (the arcs' cells): gmsh -2 -setnumber h 4 disk_quad.geo
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; yc = 25;
a = 0.55 * R;                    // the square's half-diagonal
n = Ceil(Pi * R / 2 / h) + 1;    // points along an arc and a side of the square
m = Ceil((R - a) / h) + 1;       // points from the square to the circle
Point(1) = {0, yc, 0};
Point(2) = {R, yc, 0}; Point(3) = {0, yc + R, 0}; Point(4) = {-R, yc, 0}; Point(5) = {0, yc - R, 0};
Point(6) = {a, yc, 0}; Point(7) = {0, yc + a, 0}; Point(8) = {-a, yc, 0}; Point(9) = {0, yc - a, 0};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4}; Circle(3) = {4, 1, 5}; Circle(4) = {5, 1, 2};
Line(5) = {6, 7}; Line(6) = {7, 8}; Line(7) = {8, 9}; Line(8) = {9, 6};
Line(9) = {6, 2}; Line(10) = {7, 3}; Line(11) = {8, 4}; Line(12) = {9, 5};
Curve Loop(1) = {5, 6, 7, 8}; Plane Surface(1) = {1};
Curve Loop(2) = {9, 1, -10, -5}; Plane Surface(2) = {2};
Curve Loop(3) = {10, 2, -11, -6}; Plane Surface(3) = {3};
Curve Loop(4) = {11, 3, -12, -7}; Plane Surface(4) = {4};
Curve Loop(5) = {12, 4, -9, -8}; Plane Surface(5) = {5};
Transfinite Curve{1:8} = n;
Transfinite Curve{9:12} = m;
Transfinite Surface{1:5};
Recombine Surface{1:5};
Physical Curve("contact", 1) = {3, 4};
Physical Curve("top", 2) = {1, 2};
Physical Surface("disk", 10) = {1:5};
