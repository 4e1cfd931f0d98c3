// The 3D shear box of scenes/fe-simple-shear-cnl-3d.toml with an unstructured soil mesh:
// the base of the soil (0.1 x 0.1 m) meshed in unstructured quadrangles and extruded through
// its height (0.02 m) in `layers` layers of hexahedra; the steel plate (0.12 x 0.12 x 0.01 m)
// one hexahedron. Element size and layers: -setnumber h VALUE -setnumber layers N.
DefineConstant[ h = 0.025, layers = 2 ];
Point(1) = {0, 0, 0, h}; Point(2) = {0.1, 0, 0, h}; Point(3) = {0.1, 0.1, 0, h}; Point(4) = {0, 0.1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Recombine Surface{1};
Mesh.Algorithm = 6;
Mesh.RecombinationAlgorithm = 1;
soil[] = Extrude {0, 0, 0.02} { Surface{1}; Layers{layers}; Recombine; };
// soil[0] top, soil[1] volume, soil[2..5] the sides over lines 1..4 (y = 0, x = 0.1, y = 0.1, x = 0)
p = newp;
Point(p) = {-0.01, -0.01, -0.01, 1}; Point(p + 1) = {0.11, -0.01, -0.01, 1};
Point(p + 2) = {0.11, 0.11, -0.01, 1}; Point(p + 3) = {-0.01, 0.11, -0.01, 1};
l = newl;
Line(l) = {p, p + 1}; Line(l + 1) = {p + 1, p + 2}; Line(l + 2) = {p + 2, p + 3}; Line(l + 3) = {p + 3, p};
c = newll; Curve Loop(c) = {l, l + 1, l + 2, l + 3};
base = news; Plane Surface(base) = {c};
Transfinite Curve{l, l + 1, l + 2, l + 3} = 2; Transfinite Surface{base}; Recombine Surface{base};
plate[] = Extrude {0, 0, 0.01} { Surface{base}; Layers{1}; Recombine; };
Physical Surface("soil.bottom") = {1};
Physical Surface("soil.top") = {soil[0]};
Physical Surface("soil.front") = {soil[2]};
Physical Surface("soil.right") = {soil[3]};
Physical Surface("soil.back") = {soil[4]};
Physical Surface("soil.left") = {soil[5]};
Physical Surface("plate.top") = {plate[0]};
Physical Volume("soil") = {soil[1]};
Physical Volume("plate") = {plate[1]};
Physical Volume("plate.all") = {plate[1]};
Physical Volume("soil.all") = {soil[1]};
