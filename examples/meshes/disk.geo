// The 2D disk of docs/design.md §7: radius 20, centre (0, 25), 5 above the plane y = 0.
// Physical groups (regions): 1 = lower half of the circle (contact boundary),
// 2 = upper half, 10 = the disk. Mesh size h: gmsh -2 -setnumber h 4 disk.geo
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; yc = 25;
Point(1) = {0, yc, 0, h};
Point(2) = {R, yc, 0, h};
Point(3) = {0, yc + R, 0, h};
Point(4) = {-R, yc, 0, h};
Point(5) = {0, yc - R, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {3, 4};
Physical Curve("top", 2) = {1, 2};
Physical Surface("disk", 10) = {1};
