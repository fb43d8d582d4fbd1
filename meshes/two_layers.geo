// A 1 x 1 x 1 block meshed by Gmsh into 12 x 8 x (9 + 6) hexahedra by
// extrusion with Layers + Recombine: two volumes stacked in z, "rock" below
// z = 0.6 and "cap" above, sharing the internal surface "fault" at z = 0.6;
// the six sides are tagged xmin, xmax, ymin, ymax, zmin, zmax.
// Regenerate with: gmsh -3 two_layers.geo -o two_layers.msh
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;

Point(1) = {0, 0, 0, 1.0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{12}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{8}; Recombine; };
v1[] = Extrude {0, 0, 0.6} { Surface{s[1]}; Layers{9}; Recombine; };
v2[] = Extrude {0, 0, 0.4} { Surface{v1[0]}; Layers{6}; Recombine; };

Physical Volume("rock", 1) = {v1[1]};
Physical Volume("cap", 2) = {v2[1]};
e = 1e-6;
Physical Surface("xmin", 11) = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 1 + e};
Physical Surface("xmax", 12) = Surface In BoundingBox{1 - e, -e, -e, 1 + e, 1 + e, 1 + e};
Physical Surface("ymin", 13) = Surface In BoundingBox{-e, -e, -e, 1 + e, e, 1 + e};
Physical Surface("ymax", 14) = Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 1 + e, 1 + e};
Physical Surface("zmin", 15) = Surface In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Surface("zmax", 16) = Surface In BoundingBox{-e, -e, 1 - e, 1 + e, 1 + e, 1 + e};
Physical Surface("fault", 17) = {v1[0]};
