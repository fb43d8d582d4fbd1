// A normal fault through a layered block, for the tutorial "A fault
// reactivated by depletion" (doc/tutorials/fault_depletion.md, deck
// input/tutorial_fault.nml). The block is 3 km (x) by 1 km (y), from
// z = -3000 m to -1500 m (the rock above is not meshed: &geostatic
// surface_stress carries it): overburden down to -2000 m, a 100 m reservoir,
// underburden. The fault dips 60 degrees towards +x, through (1500, -2250),
// and cuts the whole block, so it parts the reservoir into two fault blocks.
// The cross-section (x, z) is meshed with transfinite quadrangles on both
// sides of the fault line, finer towards it, then extruded along y into
// hexahedra; the fault's nodes are shared, and geoblock splits them.
// Regenerate with (Gmsh 4.8): gmsh -3 fault_reservoir.geo -o fault_reservoir.msh
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;

W = 3000; D = 1000;                        // x and y extents [m]
zl[] = {-3000, -2100, -2000, -1500};       // bottom, reservoir bottom and top, top
nz[] = {8, 4, 6};                          // cells per layer, bottom up
nx = 16;                                   // cells on each side of the fault
ny = 6;
dip = 60 * Pi / 180; xc = 1500; zc = -2250;

For i In {0:3}
  xf = xc + (zl[i] - zc) / Tan(dip);       // the fault at this level
  pl[i] = newp; Point(pl[i]) = {0, 0, zl[i], 1};
  pf[i] = newp; Point(pf[i]) = {xf, 0, zl[i], 1};
  pr[i] = newp; Point(pr[i]) = {W, 0, zl[i], 1};
  hl[i] = newl; Line(hl[i]) = {pl[i], pf[i]};       // left of the fault
  hr[i] = newl; Line(hr[i]) = {pf[i], pr[i]};       // right of it
  Transfinite Curve{hl[i]} = nx + 1 Using Progression 0.85;
  Transfinite Curve{hr[i]} = nx + 1 Using Progression 1 / 0.85;
EndFor
For i In {0:2}
  vl[i] = newl; Line(vl[i]) = {pl[i], pl[i + 1]};
  vf[i] = newl; Line(vf[i]) = {pf[i], pf[i + 1]};
  vr[i] = newl; Line(vr[i]) = {pr[i], pr[i + 1]};
  Transfinite Curve{vl[i], vf[i], vr[i]} = nz[i] + 1;
  cl = newll; Curve Loop(cl) = {hl[i], vf[i], -hl[i + 1], -vl[i]};
  sl[i] = news; Plane Surface(sl[i]) = {cl};
  cr = newll; Curve Loop(cr) = {hr[i], vr[i], -hr[i + 1], -vf[i]};
  sr[i] = news; Plane Surface(sr[i]) = {cr};
  Transfinite Surface{sl[i], sr[i]};
  Recombine Surface{sl[i], sr[i]};
EndFor

// extrude along y: each extruded surface gives [top, volume, lateral ...]
For i In {0:2}
  el[] = Extrude {0, D, 0} { Surface{sl[i]}; Layers{ny}; Recombine; };
  er[] = Extrude {0, D, 0} { Surface{sr[i]}; Layers{ny}; Recombine; };
  voll[i] = el[1]; volr[i] = er[1];
EndFor

Physical Volume("underburden", 1) = {voll[0], volr[0]};
Physical Volume("reservoir", 2) = {voll[1], volr[1]};
Physical Volume("overburden", 3) = {voll[2], volr[2]};
e = 1e-3;
Physical Surface("xmin", 11) = Surface In BoundingBox{-e, -e, -3000 - e, e, D + e, -1500 + e};
Physical Surface("xmax", 12) = Surface In BoundingBox{W - e, -e, -3000 - e, W + e, D + e, -1500 + e};
Physical Surface("ymin", 13) = Surface In BoundingBox{-e, -e, -3000 - e, W + e, e, -1500 + e};
Physical Surface("ymax", 14) = Surface In BoundingBox{-e, D - e, -3000 - e, W + e, D + e, -1500 + e};
Physical Surface("zmin", 15) = Surface In BoundingBox{-e, -e, -3000 - e, W + e, D + e, -3000 + e};
Physical Surface("zmax", 16) = Surface In BoundingBox{-e, -e, -1500 - e, W + e, D + e, -1500 + e};
// the fault: the surfaces swept by the fault's line segments
fs[] = {};
For i In {0:2}
  fs[] += Surface In BoundingBox{xc + (zl[i] - zc) / Tan(dip) - e, -e, zl[i] - e,
                                 xc + (zl[i + 1] - zc) / Tan(dip) + e, D + e, zl[i + 1] + e};
EndFor
Physical Surface("fault", 17) = {fs[]};
