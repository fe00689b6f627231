// Two disks of docs/design.md §7 (radius 20) one above the other, mirror
// images through the line y = 0, 1 apart there: the upper centred at
// (0, 20.5), the lower at (0, -20.5). Physical groups (regions): 1 = the
// upper disk's lower half, 2 = the lower disk's upper half (the contact
// pair), 3 = the upper disk's upper half, 4 = the lower disk's lower half;
// cell regions 10 (upper) and 11 (lower). Mesh size h:
// gmsh -2 -setnumber h 4 two_disks.geo
DefineConstant[ h = {4, Name "mesh size"} ];
R = 20; yc = 20.5;
For k In {0:1}
  s = 1 - 2 * k;  // +1: the upper disk, -1: the lower
  c = newp; Point(c) = {0, s * yc, 0, h};
  e = newp; Point(e) = {R, s * yc, 0, h};
  n = newp; Point(n) = {0, s * yc + R, 0, h};
  w = newp; Point(w) = {-R, s * yc, 0, h};
  d = newp; Point(d) = {0, s * yc - R, 0, h};
  a1 = newc; Circle(a1) = {e, c, n};
  a2 = newc; Circle(a2) = {n, c, w};
  a3 = newc; Circle(a3) = {w, c, d};
  a4 = newc; Circle(a4) = {d, c, e};
  l = newll; Curve Loop(l) = {a1, a2, a3, a4};
  f = news; Plane Surface(f) = {l};
  If (k == 0)
    Physical Curve("upper_contact", 1) = {a3, a4};
    Physical Curve("upper_top", 3) = {a1, a2};
    Physical Surface("upper", 10) = {f};
  Else
    Physical Curve("lower_contact", 2) = {a1, a2};
    Physical Curve("lower_bottom", 4) = {a3, a4};
    Physical Surface("lower", 11) = {f};
  EndIf
EndFor
