// The 2D shear box of scenes/fe-simple-shear-cnl-2d.toml as an unstructured all-quad mesh:
// soil 0.1 x 0.02 m on a steel plate 0.12 x 0.01 m. Element size: -setnumber h VALUE.
DefineConstant[ h = 0.0025 ];
Point(1) = {0, 0, 0, h};     Point(2) = {0.1, 0, 0, h};
Point(3) = {0.1, 0.02, 0, h}; Point(4) = {0, 0.02, 0, h};
Point(5) = {-0.01, -0.01, 0, h}; Point(6) = {0.11, -0.01, 0, h};
Point(7) = {0.11, 0, 0, h};   Point(8) = {-0.01, 0, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{5, 6, 7, 8} = 2;  // the rigid plate: one element
Transfinite Surface{2};
Recombine Surface{1, 2};
Mesh.Algorithm = 6;  // frontal-Delaunay, then Blossom recombination into quadrangles
Mesh.RecombinationAlgorithm = 1;
Mesh.SubdivisionAlgorithm = 0;
Physical Curve("soil.bottom") = {1};
Physical Curve("soil.right") = {2};
Physical Curve("soil.top") = {3};
Physical Curve("soil.left") = {4};
Physical Curve("plate.top") = {7};
Physical Surface("soil") = {1};
Physical Surface("plate") = {2};
Physical Surface("plate.all") = {2};
Physical Surface("soil.all") = {1};
