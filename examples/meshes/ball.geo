// The 3D ball of docs/design.md §7: radius 20, centre (0, 0, 25), 5 above the plane z = 0.
// Physical groups (regions): 1 = lower hemisphere (contact boundary),
// 2 = upper hemisphere, 10 = the ball. Mesh size h: gmsh -3 -setnumber h 4 ball.geo
SetFactory("OpenCASCADE");
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; zc = 25;
Sphere(1) = {0, 0, zc, R, -Pi/2, 0, 2*Pi};
Sphere(2) = {0, 0, zc, R, 0, Pi/2, 2*Pi};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
eps = 1e-3;
lower[] = Surface In BoundingBox{-R-1, -R-1, zc-R-1, R+1, R+1, zc+eps};
upper[] = Surface In BoundingBox{-R-1, -R-1, zc-eps, R+1, R+1, zc+R+1};
equator[] = Surface In BoundingBox{-R-1, -R-1, zc-eps, R+1, R+1, zc+eps};
lower[] -= equator[];
upper[] -= equator[];
Physical Surface("contact", 1) = lower[];
Physical Surface("top", 2) = upper[];
Physical Volume("ball", 10) = Volume{:};
MeshSize{ PointsOf{ Volume{:}; } } = h;
Mesh.MeshSizeMax = h;
