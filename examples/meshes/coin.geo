// A coin for the disk-on-a-cylinder scene (examples/scenes/disk_cylinder.toml):
// radius 10, thickness 4, its axis along x, centre (0, 0, 15), 5 above the
// top z = 0 of a rigid cylinder of radius 20 along x. Physical groups
// (regions): 1 = the rim (contact boundary), 2 = the two faces, 10 = the
// coin. Mesh size h: gmsh -3 -setnumber h 2 coin.geo -format msh41
SetFactory("OpenCASCADE");
DefineConstant[ h = {2, Name "mesh size"} ];
Cylinder(1) = {-2, 0, 15, 4, 0, 0, 10};
faces[] = Surface In BoundingBox{-2.1, -11, 4, -1.9, 11, 26};
faces[] += Surface In BoundingBox{1.9, -11, 4, 2.1, 11, 26};
all[] = Boundary{ Volume{1}; };
rim[] = all[];
rim[] -= faces[];
Physical Surface("rim", 1) = rim[];
Physical Surface("faces", 2) = faces[];
Physical Volume("coin", 10) = {1};
MeshSize{ PointsOf{ Volume{:}; } } = h;
Mesh.MeshSizeMax = h;
