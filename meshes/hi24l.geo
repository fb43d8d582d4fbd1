// The High Island 24L stand-in: a faulted, layered block of the Texas shelf
// (12 km east x 8 km north x 4 km deep, z = -4000 .. 0 m at the sea bed)
// with 32 faults, meshed with hexahedra only, for the contact benchmark of
// the seed (issue 16). The field's own model (Ruiz 2019) is not public: the
// layers, faults and sizes below are ours, chosen to match its size (n_u,
// n_t) and its character (one main set of growth faults striking NE-SW,
// antithetic faults, cross faults and splays; faults that cut the column and
// faults that end inside it; intersections). doc/meshes.md, "The High
// Island 24L stand-in" has the tables.
//
// How the mesh is made: the map (the plane z = 0) with the fault traces cut
// into it is meshed with quadrangles and extruded downwards through the
// layers (Layers + Recombine), one volume per layer and map face. Every fault
// is then vertical and every cell a hexahedron whose nodes are shared across
// the faults (a conforming mesh, split by geoblock). meshes/make_hi24l.py
// then tilts the faults by one shear (the layers stay flat), rebuilds the
// fault and side sets from the cells' faces (Gmsh's quads on a trace that
// ends inside a map face are not the cells' faces), checks the cells and
// counts the unknowns, and writes the mesh geoblock reads.
//
// Parameters (change with -setnumber NAME VALUE):
//   refine  scales every cell size by 1/refine and every layer's cell count
//           by refine (rounded, at least 1): 1 is the full size (845,970
//           nodes after the split, 63,980 interface elements), 0.5 the
//           medium size, 0.1 the small test mesh (meshes/hi24l_small.msh).
//           Gmsh's recombination leaves a few triangles at some values (0.12
//           for one); make_hi24l.py refuses them: move refine a little.
//
// Regenerate (in meshes/):
//   gmsh -3 hi24l.geo -setnumber refine 0.1 -o hi24l_small.msh
//   python3 make_hi24l.py hi24l_small.msh      (tilt, sets, checks, counts)
// and the same with refine 0.5 (hi24l_medium.msh) or 1 (hi24l_full.msh).
// Checked with Gmsh 4.8.4.

SetFactory("OpenCASCADE");
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
Geometry.Tolerance = 1e-6;

DefineConstant[ refine = {0.1, Min 0.05, Max 2, Name "Parameters/refine"} ];

// ---- the block --------------------------------------------------------------
LX = 12000;                  // east [m]
LY = 8000;                   // north [m]
// Map cell sizes (Gmsh's targets; the full-quad recombination then halves
// every cell). The fault map is dense (94 km of traces in 96 km^2), so cells
// refined along the traces would give far more interface elements per node
// than the seed's case (63,678 for 853,006 nodes); the traces are therefore
// meshed coarser than the rock between them, which puts the seed's ratio in
// reach.
h_fault = 115 / refine;      // along the traces [m]
h_far = 66 / refine;          // away from them [m]
d_near = 0;                  // distance from a trace within which cells stay h_fault [m]
d_far = 250;                 // distance beyond which cells are h_far [m]
z_ref = -1600;               // depth of the fault map (the traces below) [m]
// make_hi24l.py's tilt (see there): the faults are sheared about z_ref so
// that one striking at right angles to tilt_azimuth dips tilt_dip towards
// it; they turn vertical within tilt_taper of the sides
tilt_dip = 80;               // [degrees]
tilt_azimuth = 150;          // [degrees clockwise from north]: SSE, the main set's dip direction
tilt_taper = 2000;           // [m]

// ---- the layers, from the sea bed down --------------------------------------
// names are the physical volumes (regions of the deck), thicknesses [m], and
// cells across each layer at refine = 1
LAYER_NAME[] = Str("overburden_1", "overburden_2", "overburden_3", "caprock",
                   "sand_1", "shale_1", "sand_2", "shale_2", "sand_3",
                   "underburden_1", "underburden_2");
LAYER_H[] = {500, 500, 450, 100, 60, 40, 80, 40, 80, 850, 1300};
LAYER_N[] = {12, 12, 11, 7, 7, 4, 7, 4, 7, 12, 12};
NL = #LAYER_H[];

// ---- the faults ---------------------------------------------------------------
// One row per fault f01..f32 (the physical surfaces of the same names). The
// traces are those of the fault map at the reservoir level z
// = z_ref (make_hi24l.py tilts each fault about that level).
//   FKIND 0: a segment from (FA, FB) to (FC, FD) [m];
//   FKIND 1: a splay starting on fault FA at the fraction FB of its trace,
//            running FC metres along the strike (a T in map view).
//   FAZ:     strike azimuth [degrees clockwise from north]; the fault dips to
//            the right of the strike (the right-hand rule).
//   FTOP, FBOT: the fault cuts the layers FTOP..FBOT (1 = overburden_1, 11 =
//            underburden_2): a fault that does not reach the sea bed or the
//            bottom ends at a layer boundary, with a tip line inside.
// f01-f10: the main growth faults, strike N60E, dipping SSE;
// f11-f18: antithetic faults in their hanging walls, dipping NNW;
// f19-f24: cross faults, strike N150E / N330E, near vertical, crossing main
//          faults (f20 starts on f03);
// f25-f30: synthetic splays branching off a main fault;
// f31-f32: two short deep faults off the trend.
FKIND[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
           0, 0, 0, 0, 0, 0, 0, 0,
           0, 1, 0, 0, 0, 0,
           1, 1, 1, 1, 1, 1,
           0, 0};
FA[] = {0, 0, 0, 0, 3481, 5200, 8600, 7410, 10409, 6969,
        3804, 3269, 6646, 5851, 10787, 8519, 10668, 2175,
        2300, 3, 8650, 2000, 9850, 6875,
        2, 3, 4, 5, 6, 7,
        11163, 2130};
FB[] = {6813, 4850, 2887, 924, 971, 0, 0, 7165, 4971, 5929,
        6411, 4139, 6089, 3667, 6517, 3244, 2522, 7433,
        6905, 0.9, 4299, 1434, 7079, 6427,
        0.72, 0.35, 0.62, 0.45, 0.75, 0.5,
        6124, 921};
FC[] = {2056, 5456, 5678, 10599, 9543, 12000, 12000, 8856, 12000, 9567,
        1206, 1536, 4741, 4638, 8449, 6354, 8503, 616,
        4500, 3000, 10150, 1000, 10750, 5967,
        1100, 1100, 1000, 500, 900, 1200,
        11437, 3070};
FD[] = {8000, 8000, 6165, 7043, 4471, 3926, 1963, 8000, 5889, 7429,
        4911, 3139, 4989, 2967, 5167, 1994, 1272, 6533,
        3095, 0, 1701, 3166, 5521, 8000,
        0, 0, 0, 0, 0, 0,
        6876, 579};
FAZ[] = {60, 60, 60, 60, 60, 60, 60, 60, 60, 60,
         240, 240, 240, 240, 240, 240, 240, 240,
         150, 150, 150, 330, 150, 330,
         100, 25, 100, 25, 100, 25,
         20, 110};
FTOP[] = {1, 1, 1, 1, 2, 1, 4, 3, 1, 5,
          1, 1, 2, 1, 1, 3, 1, 1,
          1, 3, 4, 3, 1, 1,
          1, 2, 3, 3, 1, 5,
          6, 5};
FBOT[] = {9, 11, 11, 11, 11, 11, 11, 10, 11, 11,
          9, 9, 9, 7, 9, 9, 9, 8,
          11, 11, 11, 10, 9, 8,
          9, 9, 10, 9, 9, 11,
          11, 11};
NF = #FKIND[];

// ---- the map: the rectangle with the traces cut into it -------------------------
// end points of every trace (a splay's start on its host's trace)
For i In {0:NF-1}
  If (FKIND[i] == 0)
    PX0[i] = FA[i]; PY0[i] = FB[i]; PX1[i] = FC[i]; PY1[i] = FD[i];
  Else
    hst = FA[i] - 1;
    PX0[i] = PX0[hst] + FB[i] * (PX1[hst] - PX0[hst]);
    PY0[i] = PY0[hst] + FB[i] * (PY1[hst] - PY0[hst]);
    PX1[i] = PX0[i] + FC[i] * Sin(FAZ[i] * Pi / 180);
    PY1[i] = PY0[i] + FC[i] * Cos(FAZ[i] * Pi / 180);
  EndIf
EndFor
Rectangle(1) = {0, 0, 0, LX, LY};
For i In {0:NF-1}
  Point(1001 + 2 * i) = {PX0[i], PY0[i], 0};
  Point(1002 + 2 * i) = {PX1[i], PY1[i], 0};
  Line(1001 + i) = {1001 + 2 * i, 1002 + 2 * i};
EndFor
BooleanFragments{ Surface{1}; Delete; }{ Curve{1001:1000 + NF}; Delete; }

// map cell size: h_fault along the traces, growing to h_far away from them
e = 0.01;
trace[] = {};
allc[] = Curve{:};
For i In {0:#allc[]-1}
  bb[] = BoundingBox Curve{allc[i]};
  side = (bb[3] - bb[0] < 1 && (bb[0] < e || bb[3] > LX - e)) ||
         (bb[4] - bb[1] < 1 && (bb[1] < e || bb[4] > LY - e));
  If (!side)
    trace[] += allc[i];
  EndIf
EndFor
// A trace that ends inside a map face is an internal edge of that face,
// which the 2D mesher ignores unless it is embedded: embed each such curve in
// the smallest face whose bounding box holds it (make_hi24l.py checks that
// every fault is made of cell faces, so a wrong choice would not pass).
surf[] = Surface{:};
bnd[] = {};
For i In {0:#surf[]-1}
  bnd[] += Abs(Boundary{ Surface{surf[i]}; });
EndFor
For i In {0:#trace[]-1}
  inside = 0;
  For j In {0:#bnd[]-1}
    If (bnd[j] == trace[i])
      inside = 1;
    EndIf
  EndFor
  If (!inside)
    cb[] = BoundingBox Curve{trace[i]};
    best = -1; best_area = 1e30;
    For j In {0:#surf[]-1}
      sb[] = BoundingBox Surface{surf[j]};
      If (sb[0] <= cb[0] + e && sb[1] <= cb[1] + e && sb[3] >= cb[3] - e && sb[4] >= cb[4] - e &&
          (sb[3] - sb[0]) * (sb[4] - sb[1]) < best_area)
        best = surf[j]; best_area = (sb[3] - sb[0]) * (sb[4] - sb[1]);
      EndIf
    EndFor
    Curve{trace[i]} In Surface{best};
  EndIf
EndFor
Field[1] = Distance;
Field[1].CurvesList = {trace[]};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 2 * h_fault;   // x 2: the full-quad recombination halves every cell
Field[2].SizeMax = 2 * h_far;
Field[2].DistMin = d_near;
Field[2].DistMax = d_far;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 1;                 // MeshAdapt: quadrangles only after the recombination below at every size tried (Frontal-Delaunay 6 left a few triangles at some sizes, 8 crashes on crossing traces in Gmsh 4.8.4)
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 2;    // simple full-quad: quadrangles only
Mesh.Smoothing = 0;                 // smoothing moved the nodes on the traces and the recombined cells then straddled them

// ---- the layers: the map extruded downwards ------------------------------------
ztop = 0;
For k In {0:NL-1}
  zbot = ztop - LAYER_H[k];
  top[] = Surface In BoundingBox{-e, -e, ztop - e, LX + e, LY + e, ztop + e};
  nk = Round(LAYER_N[k] * refine);
  If (nk < 1)
    nk = 1;
  EndIf
  Extrude {0, 0, -LAYER_H[k]} { Surface{top[]}; Layers{nk}; Recombine; }
  ZTOP[k] = ztop;
  ZBOT[k] = zbot;
  ztop = zbot;
EndFor

// ---- physical groups ---------------------------------------------------------
For k In {0:NL-1}
  Physical Volume(Str(LAYER_NAME[k]), 101 + k) =
    Volume In BoundingBox{-e, -e, ZBOT[k] - e, LX + e, LY + e, ZTOP[k] + e};
EndFor
Physical Surface("xmin", 1) = Surface In BoundingBox{-e, -e, ZBOT[NL-1] - e, e, LY + e, e};
Physical Surface("xmax", 2) = Surface In BoundingBox{LX - e, -e, ZBOT[NL-1] - e, LX + e, LY + e, e};
Physical Surface("ymin", 3) = Surface In BoundingBox{-e, -e, ZBOT[NL-1] - e, LX + e, e, e};
Physical Surface("ymax", 4) = Surface In BoundingBox{-e, LY - e, ZBOT[NL-1] - e, LX + e, LY + e, e};
Physical Surface("zmin", 5) = Surface In BoundingBox{-e, -e, ZBOT[NL-1] - e, LX + e, LY + e, ZBOT[NL-1] + e};
Physical Surface("zmax", 6) = Surface In BoundingBox{-e, -e, -e, LX + e, LY + e, e};

// a fault: the vertical surfaces in the layers FTOP..FBOT whose horizontal
// extent lies on its trace
For i In {0:NF-1}
  x0 = PX0[i]; y0 = PY0[i]; dx = PX1[i] - x0; dy = PY1[i] - y0;
  len = Sqrt(dx * dx + dy * dy);
  zt = ZTOP[FTOP[i] - 1]; zb = ZBOT[FBOT[i] - 1];
  cand[] = Surface In BoundingBox{Min(x0, x0 + dx) - 1, Min(y0, y0 + dy) - 1, zb - e,
                                  Max(x0, x0 + dx) + 1, Max(y0, y0 + dy) + 1, zt + e};
  mine[] = {};
  For j In {0:#cand[]-1}
    bb[] = BoundingBox Surface{cand[j]};
    If (bb[5] - bb[2] > 1)
      // the two diagonals of the box: one of them is the surface's trace
      da = Fabs(dx * (bb[1] - y0) - dy * (bb[0] - x0)) + Fabs(dx * (bb[4] - y0) - dy * (bb[3] - x0));
      db = Fabs(dx * (bb[4] - y0) - dy * (bb[0] - x0)) + Fabs(dx * (bb[1] - y0) - dy * (bb[3] - x0));
      If (Min(da, db) < 0.05 * len)
        mine[] += cand[j];
      EndIf
    EndIf
  EndFor
  If (#mine[] == 0)
    Error("fault %g: no surface found on its trace", i + 1);
  EndIf
  Physical Surface(Sprintf("f%02g", i + 1), 201 + i) = {mine[]};
EndFor
