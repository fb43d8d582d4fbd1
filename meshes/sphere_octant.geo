// The octant x, y, z >= 0 of a sphere of radius R, meshed by Gmsh into
// hexahedra: a central cube [0, a]^3 of n x n x n cells and three blocks of
// n x n x 2n cells (2n radial layers) between its faces x = a, y = a, z = a
// and the sphere (transfinite + recombine): the layout of
// meshes/make_sphere_octant.py --level L for n = 2^L (which needs no Gmsh;
// its nodes differ a little inside the outer blocks). Physical groups:
// the volume "sphere", the surfaces "xsym" (x = 0), "ysym" (y = 0), "zsym"
// (z = 0) and "outer" (the sphere), as input/cryer.nml expects.
// Regenerate with: gmsh -3 sphere_octant.geo -o sphere_octant.msh
// (other sizes: gmsh -3 -setnumber n 16 -setnumber R 2 sphere_octant.geo -o ...)
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;

DefineConstant[ R = 1.0, n = 8, core = 0.35 ];   // radius [m], cells per block edge, a / R
a = core * R;
s2 = R / Sqrt(2);
s3 = R / Sqrt(3);

Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};   Point(3) = {0, a, 0};   Point(4) = {0, 0, a};
Point(5) = {a, a, 0};   Point(6) = {0, a, a};   Point(7) = {a, 0, a};
Point(8) = {a, a, a};
Point(9) = {R, 0, 0};   Point(10) = {0, R, 0};  Point(11) = {0, 0, R};
Point(12) = {s2, s2, 0}; Point(13) = {0, s2, s2}; Point(14) = {s2, 0, s2};
Point(15) = {s3, s3, s3};

// edges of the central cube
Line(1) = {1, 2};  Line(2) = {1, 3};  Line(3) = {1, 4};
Line(4) = {2, 5};  Line(5) = {3, 5};  Line(6) = {3, 6};
Line(7) = {4, 6};  Line(8) = {2, 7};  Line(9) = {4, 7};
Line(10) = {5, 8}; Line(11) = {6, 8}; Line(12) = {7, 8};
// from the cube to the sphere
Line(13) = {2, 9};  Line(14) = {3, 10}; Line(15) = {4, 11}; Line(16) = {5, 12};
Line(17) = {6, 13}; Line(18) = {7, 14}; Line(19) = {8, 15};
// great-circle arcs on the sphere
Circle(20) = {9, 1, 12};  Circle(21) = {10, 1, 12}; Circle(22) = {10, 1, 13};
Circle(23) = {11, 1, 13}; Circle(24) = {9, 1, 14};  Circle(25) = {11, 1, 14};
Circle(26) = {12, 1, 15}; Circle(27) = {13, 1, 15}; Circle(28) = {14, 1, 15};

// cube faces: z = 0, y = 0, x = 0, x = a, y = a, z = a
Curve Loop(1) = {1, 4, -5, -2};   Plane Surface(1) = {1};
Curve Loop(2) = {1, 8, -9, -3};   Plane Surface(2) = {2};
Curve Loop(3) = {2, 6, -7, -3};   Plane Surface(3) = {3};
Curve Loop(4) = {4, 10, -12, -8}; Plane Surface(4) = {4};
Curve Loop(5) = {5, 10, -11, -6}; Plane Surface(5) = {5};
Curve Loop(6) = {9, 12, -11, -7}; Plane Surface(6) = {6};
// block beyond x = a: sphere patch, sides z = 0, y = 0, x = y, x = z
Curve Loop(7) = {20, 26, -28, -24};  Surface(7) = {7} In Sphere {1};
Curve Loop(8) = {13, 20, -16, -4};   Plane Surface(8) = {8};
Curve Loop(9) = {13, 24, -18, -8};   Plane Surface(9) = {9};
Curve Loop(10) = {16, 26, -19, -10}; Plane Surface(10) = {10};
Curve Loop(11) = {18, 28, -19, -12}; Plane Surface(11) = {11};
// block beyond y = a: sphere patch, sides z = 0, x = 0, y = z
Curve Loop(12) = {21, 26, -27, -22}; Surface(12) = {12} In Sphere {1};
Curve Loop(13) = {14, 21, -16, -5};  Plane Surface(13) = {13};
Curve Loop(14) = {14, 22, -17, -6};  Plane Surface(14) = {14};
Curve Loop(15) = {17, 27, -19, -11}; Plane Surface(15) = {15};
// block beyond z = a: sphere patch, sides y = 0, x = 0
Curve Loop(16) = {25, 28, -27, -23}; Surface(16) = {16} In Sphere {1};
Curve Loop(17) = {15, 25, -18, -9};  Plane Surface(17) = {17};
Curve Loop(18) = {15, 23, -17, -7};  Plane Surface(18) = {18};

Surface Loop(1) = {1, 2, 3, 4, 5, 6};        Volume(1) = {1};
Surface Loop(2) = {4, 7, 8, 9, 10, 11};      Volume(2) = {2};
Surface Loop(3) = {5, 12, 13, 14, 10, 15};   Volume(3) = {3};
Surface Loop(4) = {6, 16, 17, 18, 11, 15};   Volume(4) = {4};

Transfinite Curve{1:12, 20:28} = n + 1;
Transfinite Curve{13:19} = 2 * n + 1;
Transfinite Surface{1:18};
Recombine Surface{1:18};
// corners bottom face then top, each right-handed
Transfinite Volume{1} = {1, 2, 5, 3, 4, 7, 8, 6};
Transfinite Volume{2} = {2, 5, 8, 7, 9, 12, 15, 14};
Transfinite Volume{3} = {3, 6, 8, 5, 10, 13, 15, 12};
Transfinite Volume{4} = {4, 7, 8, 6, 11, 14, 15, 13};
Recombine Volume{1:4};

Physical Volume("sphere", 10) = {1, 2, 3, 4};
Physical Surface("xsym", 1) = {3, 14, 18};
Physical Surface("ysym", 2) = {2, 9, 17};
Physical Surface("zsym", 3) = {1, 8, 13};
Physical Surface("outer", 4) = {7, 12, 16};
