// Two balls of docs/design.md §7 (radius 20) one above the other, mirror
// images through the plane z = 0, 1 apart there: the upper centred at
// (0, 0, 20.5), the lower at (0, 0, -20.5). Physical groups (regions):
// 1 = the upper ball's lower hemisphere, 2 = the lower ball's upper
// hemisphere (the contact pair), 3 = the upper ball's upper hemisphere,
// 4 = the lower ball's lower hemisphere; cell regions 10 (upper) and 11
// (lower). Mesh size h: gmsh -3 -setnumber h 4 two_balls.geo
SetFactory("OpenCASCADE");
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; zc = 20.5;
Sphere(1) = {0, 0, zc, R, -Pi/2, 0, 2*Pi};
Sphere(2) = {0, 0, zc, R, 0, Pi/2, 2*Pi};
Sphere(3) = {0, 0, -zc, R, -Pi/2, 0, 2*Pi};
Sphere(4) = {0, 0, -zc, R, 0, Pi/2, 2*Pi};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
BooleanFragments{ Volume{3}; Delete; }{ Volume{4}; Delete; }
eps = 1e-3;
For k In {0:1}
  c = (1 - 2 * k) * zc;
  lower[] = Surface In BoundingBox{-R-1, -R-1, c-R-1, R+1, R+1, c+eps};
  upper[] = Surface In BoundingBox{-R-1, -R-1, c-eps, R+1, R+1, c+R+1};
  equator[] = Surface In BoundingBox{-R-1, -R-1, c-eps, R+1, R+1, c+eps};
  lower[] -= equator[];
  upper[] -= equator[];
  volumes[] = Volume In BoundingBox{-R-1, -R-1, c-R-1, R+1, R+1, c+R+1};
  If (k == 0)
    Physical Surface("upper_contact", 1) = lower[];
    Physical Surface("upper_top", 3) = upper[];
    Physical Volume("upper", 10) = volumes[];
  Else
    Physical Surface("lower_contact", 2) = upper[];
    Physical Surface("lower_bottom", 4) = lower[];
    Physical Volume("lower", 11) = volumes[];
  EndIf
EndFor
MeshSize{ PointsOf{ Volume{:}; } } = h;
Mesh.MeshSizeMax = h;
