// Two blocks (examples/scenes/sliding_blocks.toml): the lower [0, 3] x [0, 1],
// the upper [0.5, 1.5] x [1.001, 1.5], 1e-3 above it. Physical groups
// (regions): 1 = the upper block's bottom (the contact pair's slave), 2 = the
// lower block's top (its master), 4 = the lower block's base (clamped);
// cell regions 10 (upper) and 11 (lower). Mesh size h:
// gmsh -2 -format msh41 -setnumber h 0.125 sliding_blocks.geo -o sliding_blocks.msh
DefineConstant[ h = {0.125, Name "mesh size"} ];
Point(1) = {0, 0, 0, h}; Point(2) = {3, 0, 0, h}; Point(3) = {3, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {0.5, 1.001, 0, h}; Point(6) = {1.5, 1.001, 0, h}; Point(7) = {1.5, 1.5, 0, h}; Point(8) = {0.5, 1.5, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Physical Curve("upper_bottom", 1) = {5};
Physical Curve("lower_top", 2) = {3};
Physical Curve("lower_base", 4) = {1};
Physical Surface("upper", 10) = {2};
Physical Surface("lower", 11) = {1};
