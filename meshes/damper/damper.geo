// Wedge under-platform damper for fricrom: a prism along x whose two upper inclined faces sit on
// the 45-degree chamfers of two neighbouring platforms (meshes/blade_sector/blade_sector.geo).
//
// Units: SI (m). Axes as the blade sector: x axial, y circumferential, z radial (+z out).
// The damper is meshed in the frame of the blade sector, in its working position: in the gap between
// this sector's +y platform edge (y = seat_y) and the next sector's -y edge, taken as this sector
// translated by the pitch p = 2 seat_y + gap in +y (flat-cascade approximation). Then
//   damper CONTACT_LEFT  = blade CONTACT_RIGHT              (node by node with the default grids)
//   damper CONTACT_RIGHT = blade CONTACT_LEFT shifted by +p in y
// The defaults of seat_y, seat_z, cham_h, cham_deg, length, n_contact_x, n_contact_s must match the
// blade's plat_wy/2, root_h + neck_h, cham_h, cham_deg, contact_lx, n_contact_x, n_contact_s.
//
// Cross-section (y-z), extruded along x over [-length/2, length/2]:
//
//        P1 ____ P2            z = seat_z + cham_h   (top, width gap, between the platform edges)
//          /    \              inclined faces: CONTACT_LEFT (P6-P1), CONTACT_RIGHT (P2-P3)
//      P6 /      \ P3          z = seat_z            (platform bottom)
//        |        |
//      P5|________|P4          z = seat_z - body_h
//
// Physical groups: DAMPER (volume), CONTACT_LEFT, CONTACT_RIGHT. Free-free (no boundary).

SetFactory("OpenCASCADE");

DefineConstant[
  lc           = {0.004,  Name "Parameters/Mesh/lc: target element size [m]"},
  n_contact_x  = {4,      Name "Parameters/Mesh/n_contact_x: element edges along x on a contact face"},
  n_contact_s  = {1,      Name "Parameters/Mesh/n_contact_s: element edges across a contact face"},
  length       = {0.030,  Name "Parameters/Damper/length: axial length [m]"},
  gap          = {0.003,  Name "Parameters/Damper/gap: gap between neighbouring platforms = top width [m]"},
  body_h       = {0.003,  Name "Parameters/Damper/body_h: height of the vertical sides below the contact faces [m]"},
  cham_h       = {0.0025, Name "Parameters/Damper/cham_h: height of the inclined faces (platform chamfer) [m]"},
  cham_deg     = {45,     Name "Parameters/Damper/cham_deg: inclination of the faces from the horizontal [deg]"},
  seat_y       = {0.015,  Name "Parameters/Damper/seat_y: y of the blade's +y platform edge [m]"},
  seat_z       = {0.015,  Name "Parameters/Damper/seat_z: z of the platform bottom [m]"}
];

eps = 1e-5;   // bounding-box tolerance for entity queries (OCC boxes are slightly enlarged)
big = 1;
cham_w = cham_h / Tan(cham_deg * Pi / 180);
x0 = -length / 2;

p1 = newp; Point(p1)   = {x0, seat_y,                  seat_z + cham_h};
           Point(p1+1) = {x0, seat_y + gap,            seat_z + cham_h};
           Point(p1+2) = {x0, seat_y + gap + cham_w,   seat_z};
           Point(p1+3) = {x0, seat_y + gap + cham_w,   seat_z - body_h};
           Point(p1+4) = {x0, seat_y - cham_w,         seat_z - body_h};
           Point(p1+5) = {x0, seat_y - cham_w,         seat_z};
l1 = newl;
For i In {0:5}
  Line(l1+i) = {p1+i, p1+((i+1)%6)};
EndFor
cll = newll; Curve Loop(cll) = {l1:l1+5};
sec = news; Plane Surface(sec) = {cll};
ex[] = Extrude {length, 0, 0} { Surface{sec}; };

cl[] = Surface In BoundingBox{-big, seat_y - cham_w - eps, seat_z - eps, big, seat_y + eps, seat_z + cham_h + eps};
cr[] = Surface In BoundingBox{-big, seat_y + gap - eps, seat_z - eps,
                              big, seat_y + gap + cham_w + eps, seat_z + cham_h + eps};
If (#cl[] != 1 || #cr[] != 1)
  Error("damper.geo: found %g left, %g right contact faces (want 1 each)", #cl[], #cr[]);
  Abort;
EndIf

// Structured contact faces: the same grid as the blade's contact strips (node-to-node contact).
cx[] = Curve In BoundingBox{-length/2 - eps, -big, -big, -length/2 + eps, big, big};
cx[] += Curve In BoundingBox{ length/2 - eps, -big, -big,  length/2 + eps, big, big};
For k In {0:1}
  If (k == 0)
    s = cl[0];
  Else
    s = cr[0];
  EndIf
  bnd[] = Boundary{ Surface{s}; };
  For j In {0:#bnd[]-1}
    c = Abs(bnd[j]);
    across = 0;
    For q In {0:#cx[]-1}
      If (cx[q] == c)
        across = 1;
      EndIf
    EndFor
    If (across)
      Transfinite Curve{c} = n_contact_s + 1;
    Else
      Transfinite Curve{c} = n_contact_x + 1;
    EndIf
  EndFor
  Transfinite Surface{s};
EndFor

MeshSize{ PointsOf{ Volume{:}; } } = lc;
Mesh.MeshSizeMax = lc;
Mesh.MeshSizeMin = 0;
Mesh.MeshSizeFromPoints = 1;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 1;

Mesh.Algorithm = 6;          // Frontal-Delaunay (2D)
Mesh.Algorithm3D = 1;        // Delaunay (3D)
Mesh.ElementOrder = 2;       // C3D10
Mesh.SecondOrderLinear = 0;
Mesh.HighOrderOptimize = 0;
Mesh.Optimize = 1;
Mesh.OptimizeNetgen = 0;
Mesh.RandomFactor = 1e-9;
General.NumThreads = 1;
Mesh.MaxNumThreads1D = 1;
Mesh.MaxNumThreads2D = 1;
Mesh.MaxNumThreads3D = 1;
Mesh.SaveAll = 0;
Mesh.SaveGroupsOfNodes = 1;

all_v[] = Volume{:};
Physical Volume("DAMPER") = {all_v[]};
Physical Surface("CONTACT_LEFT") = {cl[]};
Physical Surface("CONTACT_RIGHT") = {cr[]};
