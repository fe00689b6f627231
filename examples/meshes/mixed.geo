// A 2D mesh mixing triangles and quadrilaterals (docs/design.md §10.7): the
// rectangle [0, 2] x [0, 1] in two surfaces, the left one recombined into
// quadrilaterals, the right one left in triangles; they share the segment
// x = 1, which Gmsh meshes once. Physical groups (regions): 1 = the bottom
// y = 0 (contact boundary), 2 = the top, 10 = the quadrilaterals, 11 = the
// triangles. gmsh -2 -format msh41 mixed.geo -o mixed.msh (and -format msh22
// for mixed_v2.msh; -order 2 for the 9-node quadrilaterals and 6-node
// triangles of mixed_o2.msh).
h = 0.34;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {2, 0, 0, h};
Point(4) = {2, 1, 0, h};
Point(5) = {1, 1, 0, h};
Point(6) = {0, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7};
Plane Surface(2) = {2};
Recombine Surface{1};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("top", 2) = {4, 5};
Physical Surface("quadrilaterals", 10) = {1};
Physical Surface("triangles", 11) = {2};
