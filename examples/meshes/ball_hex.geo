// The 3D ball of docs/design.md §7 (ball.geo) in hexahedra: a transfinite
// O-grid, a cube split at the equator z = zc into two halves and ten blocks
// between it and the sphere (a cap below and above, four on the sides of
// each half), so that the equator is a curve of the sphere's patches.
// Physical groups as ball.geo's: 1 = lower hemisphere (contact boundary),
// 2 = upper hemisphere, 10 = the ball.
// Mesh size h (the sphere's cells): gmsh -3 -setnumber h 4 ball_hex.geo
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; zc = 25;
a = 0.4 * R;                                    // the cube's half-side
// points along a cube edge and its arc: odd, so that a node sits at each
// pole (the cap's centre), where the ball first touches the plane: with an
// even number the lowest point was 0.32 (h = 4) above the disk's 5
n = 2 * Ceil(R * Acos(1 / 3) / (2 * h)) + 1;
nv = Ceil(R * Acos(Sqrt(2 / 3)) / h) + 1;        // along half a vertical edge and its arc
m = Ceil((R - a) / h) + 1;                       // from the cube to the sphere
Point(1) = {0, 0, zc};
sx[] = {1, -1, -1, 1}; sy[] = {1, 1, -1, -1};   // the corners counterclockwise
sz[] = {-1, 0, 1};                              // the layers: bottom, equator, top
// P(l, c) = 10 + 4 l + c on the cube, S(l, c) = 30 + 4 l + c on the sphere
For l In {0:2}
  For c In {0:3}
    Point(10 + 4 * l + c) = {a * sx[c], a * sy[c], zc + a * sz[l]};
    r = Sqrt(2 + sz[l] * sz[l]);
    Point(30 + 4 * l + c) = {R * sx[c] / r, R * sy[c] / r, zc + R * sz[l] / r};
  EndFor
EndFor
// rings (layer l, from corner c to c + 1): cube 100 + 4 l + c, sphere 200 + 4 l + c;
// vertical (layer l to l + 1 at corner c): cube 120 + 4 l + c, sphere 220 + 4 l + c;
// radial (cube to sphere): 300 + 4 l + c
For l In {0:2}
  For c In {0:3}
    d = (c + 1) % 4;
    Line(100 + 4 * l + c) = {10 + 4 * l + c, 10 + 4 * l + d};
    Circle(200 + 4 * l + c) = {30 + 4 * l + c, 1, 30 + 4 * l + d};
    Line(300 + 4 * l + c) = {10 + 4 * l + c, 30 + 4 * l + c};
    If (l < 2)
      Line(120 + 4 * l + c) = {10 + 4 * l + c, 10 + 4 * l + 4 + c};
      Circle(220 + 4 * l + c) = {30 + 4 * l + c, 1, 30 + 4 * l + 4 + c};
    EndIf
  EndFor
EndFor
// the cube's squares 400 + l; its vertical faces 410 + 4 l + c; the sphere's
// caps 430 + l (l = 0, 2), its side patches 440 + 4 l + c; the radial faces
// of the rings 460 + 4 l + c and of the vertical edges 480 + 4 l + c
For l In {0:2}
  Curve Loop(400 + l) = {100 + 4 * l, 101 + 4 * l, 102 + 4 * l, 103 + 4 * l};
  Plane Surface(400 + l) = {400 + l};
  If (l != 1)
    Curve Loop(430 + l) = {200 + 4 * l, 201 + 4 * l, 202 + 4 * l, 203 + 4 * l};
    Surface(430 + l) = {430 + l} In Sphere {1};
  EndIf
  For c In {0:3}
    d = (c + 1) % 4;
    Curve Loop(460 + 4 * l + c) = {100 + 4 * l + c, 300 + 4 * l + d, -(200 + 4 * l + c), -(300 + 4 * l + c)};
    Plane Surface(460 + 4 * l + c) = {460 + 4 * l + c};
    If (l < 2)
      Curve Loop(410 + 4 * l + c) = {100 + 4 * l + c, 120 + 4 * l + d, -(104 + 4 * l + c), -(120 + 4 * l + c)};
      Plane Surface(410 + 4 * l + c) = {410 + 4 * l + c};
      Curve Loop(440 + 4 * l + c) = {200 + 4 * l + c, 220 + 4 * l + d, -(204 + 4 * l + c), -(220 + 4 * l + c)};
      Surface(440 + 4 * l + c) = {440 + 4 * l + c} In Sphere {1};
      Curve Loop(480 + 4 * l + c) = {120 + 4 * l + c, 304 + 4 * l + c, -(220 + 4 * l + c), -(300 + 4 * l + c)};
      Plane Surface(480 + 4 * l + c) = {480 + 4 * l + c};
    EndIf
  EndFor
EndFor
// the cube's halves 1, 2; the caps 3 (below), 4; the side blocks 5 + 4 l + c
For l In {0:1}
  Surface Loop(1 + l) = {400 + l, 401 + l, 410 + 4 * l, 411 + 4 * l, 412 + 4 * l, 413 + 4 * l};
  Volume(1 + l) = {1 + l};
  For c In {0:3}
    d = (c + 1) % 4;
    Surface Loop(5 + 4 * l + c) = {410 + 4 * l + c, 440 + 4 * l + c, 460 + 4 * l + c, 464 + 4 * l + c,
                                   480 + 4 * l + c, 480 + 4 * l + d};
    Volume(5 + 4 * l + c) = {5 + 4 * l + c};
  EndFor
EndFor
For l In {0:2:2}
  Surface Loop(3 + l / 2) = {400 + l, 430 + l, 460 + 4 * l, 461 + 4 * l, 462 + 4 * l, 463 + 4 * l};
  Volume(3 + l / 2) = {3 + l / 2};
EndFor
Transfinite Curve{100:111, 200:211} = n;
Transfinite Curve{120:127, 220:227} = nv;
Transfinite Curve{300:311} = m;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Physical Surface("contact", 1) = {430, 440:443};
Physical Surface("top", 2) = {432, 444:447};
Physical Volume("ball", 10) = {1:12};
