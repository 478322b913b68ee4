// Blade sector for fricrom: twisted, cambered blade on a platform with two 45-degree under-platform
// chamfers (the seats of wedge dampers), a neck (shank) and a root block clamped at its bottom face.
//
// Units: SI (m). Axes: x axial (flow direction), y circumferential, z radial (blade span, +z out).
// The root bottom face is the plane z = 0. Every parameter below can be overridden from the command
// line, e.g.  gmsh blade_sector.geo -3 -setnumber lc 0.003 -setnumber n_contact_x 8
// (scripts/make_meshes.sh does this for the coarse and fine variants; see meshes/README.md).
//
// Physical groups (become *NSET / *ELSET in the .inp after scripts/fix_gmsh_inp.py):
//   BLADE (volume), ROOT (z = 0 face), CONTACT_LEFT (-y chamfer strip), CONTACT_RIGHT (+y chamfer
//   strip), EXCITATION (tip vertex on the leading edge), RESPONSE (tip vertex on the trailing edge).

SetFactory("OpenCASCADE");

DefineConstant[
  // mesh
  lc           = {0.005,  Name "Parameters/Mesh/lc: target element size [m]"},
  lc_blade     = {0.005,  Name "Parameters/Mesh/lc_blade: element size on the airfoil [m]"},
  n_contact_x  = {4,      Name "Parameters/Mesh/n_contact_x: element edges along x on a contact strip"},
  n_contact_s  = {1,      Name "Parameters/Mesh/n_contact_s: element edges across a contact strip"},
  // root block and neck (shank)
  root_lx      = {0.030,  Name "Parameters/Root/root_lx: axial length [m]"},
  root_wy      = {0.014,  Name "Parameters/Root/root_wy: circumferential width [m]"},
  root_h       = {0.005,  Name "Parameters/Root/root_h: height [m]"},
  neck_lx      = {0.030,  Name "Parameters/Root/neck_lx: neck axial length [m]"},
  neck_wy      = {0.007,  Name "Parameters/Root/neck_wy: neck circumferential width [m]"},
  neck_h       = {0.010,  Name "Parameters/Root/neck_h: neck height [m]"},
  // platform
  plat_lx      = {0.040,  Name "Parameters/Platform/plat_lx: axial length [m]"},
  plat_wy      = {0.030,  Name "Parameters/Platform/plat_wy: circumferential width [m]"},
  plat_t       = {0.004,  Name "Parameters/Platform/plat_t: thickness [m]"},
  cham_h       = {0.0025, Name "Parameters/Platform/cham_h: chamfer height (vertical leg) [m]"},
  cham_deg     = {45,     Name "Parameters/Platform/cham_deg: chamfer angle from the horizontal [deg]"},
  contact_lx   = {0.030,  Name "Parameters/Platform/contact_lx: axial length of the contact strip (= damper length) [m]"},
  // airfoil
  span         = {0.050,  Name "Parameters/Airfoil/span: blade height above the platform [m]"},
  chord        = {0.030,  Name "Parameters/Airfoil/chord [m]"},
  thick_root   = {0.14,   Name "Parameters/Airfoil/thick_root: max thickness / chord at the root"},
  thick_tip    = {0.10,   Name "Parameters/Airfoil/thick_tip: max thickness / chord at the tip"},
  camber       = {0.08,   Name "Parameters/Airfoil/camber: max camber / chord"},
  te_thin      = {0.45,   Name "Parameters/Airfoil/te_thin: thickness reduction towards the trailing edge (0..1)"},
  stagger_root = {30,     Name "Parameters/Airfoil/stagger_root: chord angle to the x axis at the root [deg]"},
  stagger_tip  = {40,     Name "Parameters/Airfoil/stagger_tip: chord angle to the x axis at the tip [deg]"},
  n_prof       = {14,     Name "Parameters/Airfoil/n_prof: spline points per profile side - 1"}
];

eps = 1e-5;   // bounding-box tolerance for entity queries (OCC boxes are slightly enlarged)
z_pb = root_h + neck_h;          // platform bottom
z_pt = z_pb + plat_t;            // platform top = blade base
cham_w = cham_h / Tan(cham_deg * Pi / 180);  // chamfer horizontal leg
If (cham_h >= plat_t || cham_w >= plat_wy/2 - neck_wy/2 || contact_lx > plat_lx || neck_lx > plat_lx)
  Error("blade_sector.geo: inconsistent platform / chamfer / neck parameters");
  Abort;
EndIf

// ---------------------------------------------------------------- root block and neck
Box(1) = {-root_lx/2, -root_wy/2, 0,      root_lx, root_wy, root_h};
Box(2) = {-neck_lx/2, -neck_wy/2, root_h, neck_lx, neck_wy, neck_h};

// ---------------------------------------------------------------- platform
// Cross-section in the plane x = -plat_lx/2 (y-z), chamfered bottom corners, extruded along +x in
// three pieces so that the middle strip of each chamfer (length contact_lx) is a face of its own.
x0 = -plat_lx/2;
pp1 = newp; Point(pp1)   = {x0, -plat_wy/2 + cham_w, z_pb};
            Point(pp1+1) = {x0,  plat_wy/2 - cham_w, z_pb};
            Point(pp1+2) = {x0,  plat_wy/2,          z_pb + cham_h};
            Point(pp1+3) = {x0,  plat_wy/2,          z_pt};
            Point(pp1+4) = {x0, -plat_wy/2,          z_pt};
            Point(pp1+5) = {x0, -plat_wy/2,          z_pb + cham_h};
pl1 = newl;
For i In {0:5}
  Line(pl1+i) = {pp1+i, pp1+((i+1)%6)};
EndFor
pll = newll; Curve Loop(pll) = {pl1:pl1+5};
pls = news; Plane Surface(pls) = {pll};
ex1[] = Extrude {(plat_lx - contact_lx)/2, 0, 0} { Surface{pls}; };
ex2[] = Extrude {contact_lx, 0, 0} { Surface{ex1[0]}; };
ex3[] = Extrude {(plat_lx - contact_lx)/2, 0, 0} { Surface{ex2[0]}; };

// ---------------------------------------------------------------- airfoil
// Profile in chord units, s in [0, 1] from leading to trailing edge: parabolic camber line
// yc = 4 camber s (1 - s), half thickness yt = (t/2) sqrt(1 - u^2) (1 - te_thin (1 + u)/2),
// u = 2 s - 1 (rounded leading and trailing edges, thinner towards the trailing edge).
// Two splines per section (suction side, pressure side) meeting at the LE and TE vertices.
// Mid-chord at (x, y) = (0, 0); chord turned by the stagger angle (twist from root to tip).
nsec = 3;
For k In {0:nsec-1}
  f = k / (nsec - 1);
  zk = z_pt + f * span;
  tk = thick_root + f * (thick_tip - thick_root);
  bk = (stagger_root + f * (stagger_tip - stagger_root)) * Pi / 180;
  up[] = {};
  lo[] = {};
  For i In {0:n_prof}
    s = (1 - Cos(Pi * i / n_prof)) / 2;
    u = 2 * s - 1;
    yc = 4 * camber * s * (1 - s);
    yt = 0.5 * tk * Sqrt(Fabs(1 - u * u)) * (1 - te_thin * (1 + u) / 2);
    For side In {0:1}
      If (side == 0 || (i > 0 && i < n_prof))
        sy = yc + (1 - 2 * side) * yt;
        X = chord * (s - 0.5);
        Y = chord * sy;
        p = newp;
        Point(p) = {X * Cos(bk) - Y * Sin(bk), X * Sin(bk) + Y * Cos(bk), zk};
        If (side == 0)
          up[] += p;
        Else
          lo[] += p;
        EndIf
      EndIf
    EndFor
  EndFor
  // lower side runs TE -> LE, sharing the end points of the upper side
  lor[] = {up[n_prof]};
  For i In {0:n_prof-2}
    lor[] += lo[n_prof-2-i];
  EndFor
  lor[] += up[0];
  c1 = newl; Spline(c1) = up[];
  c2 = newl; Spline(c2) = lor[];
  w~{k} = newll; Wire(w~{k}) = {c1, c2};
EndFor
vb = newv;
ThruSections(vb) = {w~{0}, w~{1}, w~{2}};

// ---------------------------------------------------------------- conformal assembly
all[] = BooleanFragments{ Volume{1, 2, ex1[1], ex2[1], ex3[1], vb}; Delete; }{};

// ---------------------------------------------------------------- entities by location
big = 1;
root_s[] = Surface In BoundingBox{-big, -big, -eps, big, big, eps};
cl[] = Surface In BoundingBox{-contact_lx/2 - eps, -plat_wy/2 - eps, z_pb - eps,
                              contact_lx/2 + eps, -plat_wy/2 + cham_w + eps, z_pb + cham_h + eps};
cr[] = Surface In BoundingBox{-contact_lx/2 - eps, plat_wy/2 - cham_w - eps, z_pb - eps,
                              contact_lx/2 + eps, plat_wy/2 + eps, z_pb + cham_h + eps};
If (#root_s[] != 1 || #cl[] != 1 || #cr[] != 1)
  Error("blade_sector.geo: found %g root, %g left, %g right faces (want 1 each)", #root_s[], #cl[], #cr[]);
  Abort;
EndIf

// tip vertices: leading edge (s = 0) and trailing edge (s = 1) of the tip section
bt = stagger_tip * Pi / 180;
z_tip = z_pt + span;
le_x = -chord/2 * Cos(bt); le_y = -chord/2 * Sin(bt);
te_x =  chord/2 * Cos(bt); te_y =  chord/2 * Sin(bt);
d = 1e-5;
p_le[] = Point In BoundingBox{le_x - d, le_y - d, z_tip - d, le_x + d, le_y + d, z_tip + d};
p_te[] = Point In BoundingBox{te_x - d, te_y - d, z_tip - d, te_x + d, te_y + d, z_tip + d};
If (#p_le[] != 1 || #p_te[] != 1)
  Error("blade_sector.geo: tip vertices not found (%g LE, %g TE)", #p_le[], #p_te[]);
  Abort;
EndIf

// ---------------------------------------------------------------- structured contact strips
// One transfinite grid per strip: n_contact_x edges along x, n_contact_s across; the damper mesh
// uses the same grid, so the contact nodes of blade and damper coincide.
For k In {0:1}
  If (k == 0)
    s = cl[0];
  Else
    s = cr[0];
  EndIf
  cx[] = Curve In BoundingBox{-contact_lx/2 - eps, -big, -big, -contact_lx/2 + eps, big, big};
  cx[] += Curve In BoundingBox{ contact_lx/2 - eps, -big, -big,  contact_lx/2 + eps, big, big};
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

// ---------------------------------------------------------------- mesh sizes and options
// Sizes: lc on every geometric vertex, lc_blade on the vertices of the airfoil (blade base and
// tip sections, leading and trailing edges), interpolated along curves and into surfaces/volumes.
MeshSize{ PointsOf{ Volume{:}; } } = lc;
blade_faces[] = Surface In BoundingBox{-big, -big, z_pt - eps, big, big, big};
blade_faces[] -= Surface In BoundingBox{-big, -big, z_pt - eps, big, big, z_pt + eps};  // platform top
MeshSize{ PointsOf{ Surface{blade_faces[]}; } } = lc_blade;
Mesh.MeshSizeMax = lc;
Mesh.MeshSizeMin = 0;
Mesh.MeshSizeFromPoints = 1;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 1;

Mesh.Algorithm = 6;          // Frontal-Delaunay (2D)
Mesh.Algorithm3D = 1;        // Delaunay (3D)
Mesh.ElementOrder = 2;       // C3D10
Mesh.SecondOrderLinear = 0;  // mid-side nodes on the CAD surfaces
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
Physical Volume("BLADE") = {all_v[]};
Physical Surface("ROOT") = {root_s[]};
Physical Surface("CONTACT_LEFT") = {cl[]};
Physical Surface("CONTACT_RIGHT") = {cr[]};
Physical Point("EXCITATION") = {p_le[]};
Physical Point("RESPONSE") = {p_te[]};
