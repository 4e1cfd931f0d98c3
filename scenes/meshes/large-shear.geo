// Large-scale cyclic interface shear test of paper §6 (Staubach, Machacek, Wichtmann 2022,
// Fig. 8; box 1.2 m wide, 0.5 m deep, 2 m high, sand 1.56 m high), in 3D: by symmetry the
// half of the box depth, y = 0 .. 0.25 m (y = 0 the symmetry plane, y = 0.25 the box's side
// wall), x = 0 .. 1.2 m (x = 0 the left wall, x = 1.2 the moving wall), z = 0 .. 1.56 m (the
// vertical axis is z, the last; z = 0 the sand's base). All hexahedra (transfinite, extruded).
//
// Bodies (physical volumes: element set + node set of the same name):
//   soil       the sand, three stacked blocks z = 0 .. 0.51 | 0.51 .. 1.11 | 1.11 .. 1.56, so
//              that its right face x = 1.2 has edges where the wall segments meet
//   wall       the moving wall, one element thick (x = 1.2 .. 1.2 + tw, y = 0 .. 0.25), three
//              of the four segments, each 0.6 m high; they share their nodes where they meet
//              (the whole wall moves as one); sub-groups for each segment:
//   wall_low   segment 1, z = -0.09 .. 0.51 (overlaps the sand's base by 9 cm)
//   wall_rough segment 2, z = 0.51 .. 1.11 (sanded, the interface under test)
//   wall_up    segment 3, z = 1.11 .. 1.71 (its upper 0.15 m above the sand surface)
//              Segment 4, z = 1.71 .. 2.31, lies wholly above the sand (surface at 1.56, the
//              wall moves at most 5 mm down) and never touches it: it is left out.
//   side_wall  the box's side wall, one element thick (y = 0.25 .. 0.25 + tw), x = 0 .. 1.2,
//              z = 0 .. 2.0 (the box's height)
// Faces (physical surfaces: face set + node set):
//   soil.bottom (z = 0), soil.top (z = 1.56), soil.left (x = 0), soil.front (y = 0, the
//   symmetry plane), soil.back (y = 0.25, against the side wall), soil.right_low,
//   soil.right_rough, soil.right_up (x = 1.2, against segments 1, 2, 3: the slave faces);
//   wall_low.face, wall_rough.face, wall_up.face (x = 1.2) and side_wall.face (y = 0.25): the
//   master faces.
// The walls' faces coincide with the soil's but have their own nodes (contact, not shared):
// the walls are built away from the soil (y + off1, y + off2) where the built-in kernel's
// coherence cannot merge them with the soil, and moved into place after
// Geometry.AutoCoherence = 0. The wall and side-wall meshes match the soil's faces node for
// node (same divisions and gradings).
//
// Parameters (gmsh -setnumber NAME VALUE): nx, ny soil elements along x and y; nz_low,
// nz_rough, nz_up along z in the three blocks; rx ratio of neighbouring element lengths along
// x (< 1: finer towards the moving wall x = 1.2); rz the same along z in the low and upper
// blocks (finer towards the rough segment); bump the rough block's Gmsh bump coefficient
// (< 1: finer at both of its ends); nz_seg_top elements of segment 3 above the sand;
// nz_side_top elements of the side wall above the sand; tw the walls' thickness (m).
// Meshes: scripts/make_large_shear_meshes.sh (coarse and fine).
DefineConstant[ nx = 8, ny = 3, nz_low = 4, nz_rough = 5, nz_up = 3, rx = 0.8, rz = 0.8,
                bump = 0.5, nz_seg_top = 1, nz_side_top = 2, tw = 0.02 ];

W = 1.2;     // box width (x)
D = 0.25;    // half the box depth (y)
H = 1.56;    // sand height (z)
z1 = 0.51;   // segment 1 / segment 2
z2 = 1.11;   // segment 2 / segment 3
zb = -0.09;  // bottom of segment 1
zs = 1.71;   // top of segment 3
hb = 2.0;    // box height (top of the side wall)
off1 = 10.0; // where the wall is built before it is moved into place
off2 = 20.0; // the same for the side wall

// ---- the soil: cross-section in the x-z plane at y = 0, extruded along +y -----------------
p = newp;
Point(p) = {0, 0, 0};   Point(p + 1) = {W, 0, 0};
Point(p + 2) = {0, 0, z1};  Point(p + 3) = {W, 0, z1};
Point(p + 4) = {0, 0, z2};  Point(p + 5) = {W, 0, z2};
Point(p + 6) = {0, 0, H};   Point(p + 7) = {W, 0, H};
l = newl;
Line(l) = {p, p + 1};          // z = 0     (x from 0 to W)
Line(l + 1) = {p + 2, p + 3};  // z = z1
Line(l + 2) = {p + 4, p + 5};  // z = z2
Line(l + 3) = {p + 6, p + 7};  // z = H
Line(l + 4) = {p, p + 2};      // x = 0, upwards
Line(l + 5) = {p + 2, p + 4};
Line(l + 6) = {p + 4, p + 6};
Line(l + 7) = {p + 1, p + 3};  // x = W, upwards
Line(l + 8) = {p + 3, p + 5};
Line(l + 9) = {p + 5, p + 7};
Transfinite Curve{l, l + 1, l + 2, l + 3} = nx + 1 Using Progression rx;
Transfinite Curve{l + 4, l + 7} = nz_low + 1 Using Progression rz;
Transfinite Curve{l + 5, l + 8} = nz_rough + 1 Using Bump bump;
Transfinite Curve{l + 6, l + 9} = nz_up + 1 Using Progression 1 / rz;
c = newll;
Curve Loop(c) = {l, l + 7, -(l + 1), -(l + 4)};
Curve Loop(c + 1) = {l + 1, l + 8, -(l + 2), -(l + 5)};
Curve Loop(c + 2) = {l + 2, l + 9, -(l + 3), -(l + 6)};
s = news;
Plane Surface(s) = {c}; Plane Surface(s + 1) = {c + 1}; Plane Surface(s + 2) = {c + 2};
Transfinite Surface{s, s + 1, s + 2}; Recombine Surface{s, s + 1, s + 2};
// Extrude returns [back (y = D), volume, then the faces over the loop's curves in order:
// bottom, right (x = W), top, left (x = 0)].
lo[] = Extrude {0, D, 0} { Surface{s}; Layers{ny}; Recombine; };
ro[] = Extrude {0, D, 0} { Surface{s + 1}; Layers{ny}; Recombine; };
up[] = Extrude {0, D, 0} { Surface{s + 2}; Layers{ny}; Recombine; };

// ---- the moving wall (segments 1-3), built at y + off1 ------------------------------------
q = newp;
zw[] = {zb, 0, z1, z2, H, zs};
For i In {0 : 5}
  Point(q + 2 * i) = {W, off1, zw[i]};
  Point(q + 2 * i + 1) = {W + tw, off1, zw[i]};
EndFor
m = newl;
For i In {0 : 5}
  Line(m + i) = {q + 2 * i, q + 2 * i + 1};            // horizontal, one element
EndFor
For i In {0 : 4}
  Line(m + 6 + i) = {q + 2 * i, q + 2 * i + 2};        // x = W, upwards
  Line(m + 11 + i) = {q + 2 * i + 1, q + 2 * i + 3};   // x = W + tw, upwards
EndFor
Transfinite Curve{m, m + 1, m + 2, m + 3, m + 4, m + 5} = 2;
Transfinite Curve{m + 6, m + 11} = 2;
Transfinite Curve{m + 7, m + 12} = nz_low + 1 Using Progression rz;
Transfinite Curve{m + 8, m + 13} = nz_rough + 1 Using Bump bump;
Transfinite Curve{m + 9, m + 14} = nz_up + 1 Using Progression 1 / rz;
Transfinite Curve{m + 10, m + 15} = nz_seg_top + 1;
cw = newll;
sw = news;
For i In {0 : 4}
  Curve Loop(cw + i) = {m + i, m + 11 + i, -(m + i + 1), -(m + 6 + i)};
  Plane Surface(sw + i) = {cw + i};
  Transfinite Surface{sw + i}; Recombine Surface{sw + i};
EndFor
// [back, volume, bottom, right (x = W + tw), top, left (x = W: the face against the soil)]
w0[] = Extrude {0, D, 0} { Surface{sw}; Layers{ny}; Recombine; };
w1[] = Extrude {0, D, 0} { Surface{sw + 1}; Layers{ny}; Recombine; };
w2[] = Extrude {0, D, 0} { Surface{sw + 2}; Layers{ny}; Recombine; };
w3[] = Extrude {0, D, 0} { Surface{sw + 3}; Layers{ny}; Recombine; };
w4[] = Extrude {0, D, 0} { Surface{sw + 4}; Layers{ny}; Recombine; };

// ---- the side wall, built at y = D + off2, extruded along +y by tw -------------------------
r = newp;
zv[] = {0, z1, z2, H, hb};
For i In {0 : 4}
  Point(r + 2 * i) = {0, D + off2, zv[i]};
  Point(r + 2 * i + 1) = {W, D + off2, zv[i]};
EndFor
n = newl;
For i In {0 : 4}
  Line(n + i) = {r + 2 * i, r + 2 * i + 1};            // horizontal, x from 0 to W
EndFor
For i In {0 : 3}
  Line(n + 5 + i) = {r + 2 * i, r + 2 * i + 2};        // x = 0, upwards
  Line(n + 9 + i) = {r + 2 * i + 1, r + 2 * i + 3};    // x = W, upwards
EndFor
Transfinite Curve{n, n + 1, n + 2, n + 3, n + 4} = nx + 1 Using Progression rx;
Transfinite Curve{n + 5, n + 9} = nz_low + 1 Using Progression rz;
Transfinite Curve{n + 6, n + 10} = nz_rough + 1 Using Bump bump;
Transfinite Curve{n + 7, n + 11} = nz_up + 1 Using Progression 1 / rz;
Transfinite Curve{n + 8, n + 12} = nz_side_top + 1;
cs = newll;
ss = news;
For i In {0 : 3}
  Curve Loop(cs + i) = {n + i, n + 9 + i, -(n + i + 1), -(n + 5 + i)};
  Plane Surface(ss + i) = {cs + i};
  Transfinite Surface{ss + i}; Recombine Surface{ss + i};
EndFor
v0[] = Extrude {0, tw, 0} { Surface{ss}; Layers{1}; Recombine; };
v1[] = Extrude {0, tw, 0} { Surface{ss + 1}; Layers{1}; Recombine; };
v2[] = Extrude {0, tw, 0} { Surface{ss + 2}; Layers{1}; Recombine; };
v3[] = Extrude {0, tw, 0} { Surface{ss + 3}; Layers{1}; Recombine; };

// ---- move the walls into place without merging them with the soil -------------------------
Geometry.AutoCoherence = 0;
Translate {0, -off1, 0} { Volume{w0[1], w1[1], w2[1], w3[1], w4[1]}; }
Translate {0, -off2, 0} { Volume{v0[1], v1[1], v2[1], v3[1]}; }

// ---- physical groups ----------------------------------------------------------------------
Physical Volume("soil") = {lo[1], ro[1], up[1]};
Physical Volume("wall") = {w0[1], w1[1], w2[1], w3[1], w4[1]};
Physical Volume("wall_low") = {w0[1], w1[1]};
Physical Volume("wall_rough") = {w2[1]};
Physical Volume("wall_up") = {w3[1], w4[1]};
Physical Volume("side_wall") = {v0[1], v1[1], v2[1], v3[1]};

Physical Surface("soil.bottom") = {lo[2]};
Physical Surface("soil.top") = {up[4]};
Physical Surface("soil.left") = {lo[5], ro[5], up[5]};
Physical Surface("soil.front") = {s, s + 1, s + 2};
Physical Surface("soil.back") = {lo[0], ro[0], up[0]};
Physical Surface("soil.right_low") = {lo[3]};
Physical Surface("soil.right_rough") = {ro[3]};
Physical Surface("soil.right_up") = {up[3]};
Physical Surface("wall_low.face") = {w0[5], w1[5]};
Physical Surface("wall_rough.face") = {w2[5]};
Physical Surface("wall_up.face") = {w3[5], w4[5]};
Physical Surface("side_wall.face") = {ss, ss + 1, ss + 2, ss + 3};
