// Full sphere of radius R centred at (0,0,R), resting on the plane z = 0.
// Usage: gmsh -3 -order 2 -format msh41 -setnumber R 100 -setnumber h 25 sphere.geo -o sphere.msh
// Groups: volume "aggregate", surface "surface", points "pole_bottom" (0,0,0), "pole_top" (0,0,2R),
// "equator_y" (0,R,R) (a surface node off the axis: with the poles it removes the rigid modes
// frictionless plates cannot stop, see meshes/scenes/reference_full.toml).
SetFactory("OpenCASCADE");

DefineConstant[ R = 100 ];         // sphere radius
DefineConstant[ h = R / 4 ];       // element size in the bulk
DefineConstant[ h_pole = h / 3 ];  // element size at the two poles (plate contacts)
DefineConstant[ r_pole = 0.5 * R ]; // distance over which the size blends from h_pole back to h
// Optional grading at the contact edges (off unless h_edge < h), as in sphere_quarter.geo.
DefineConstant[ h_edge = h ];
DefineConstant[ r_edge = 0.62 * R ];
DefineConstant[ w_edge = 0.25 * R ];
// Optional grading towards the surface (off unless h_surf < h), as in sphere_quarter.geo.
DefineConstant[ h_surf = h ];
DefineConstant[ w_surf = 0.3 * R ];

Sphere(1) = {0, 0, R, R};

// The OCC sphere's two poles are its only geometric points: they become mesh nodes.
eps = 1e-6 * R;
pb() = Point In BoundingBox{-eps, -eps, -eps, eps, eps, eps};
pt() = Point In BoundingBox{-eps, -eps, 2 * R - eps, eps, eps, 2 * R + eps};
pe = newp;
Point(pe) = {0, R, R}; // not on the OCC seam (y = 0, x > 0), where it would not join the volume mesh
Point{pe} In Surface{1};

// Refine near the poles: size h_pole within distance 0, growing linearly to h at r_pole.
Field[1] = Distance;
Field[1].PointsList = {pb(), pt()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_pole;
Field[2].SizeMax = h;
Field[2].DistMin = 0;
Field[2].DistMax = r_pole;
// The size field: the pole threshold, and the optional contact-edge and surface gradings.
sizes() = {2};
If (h_edge < h)
  // distance to the nearer ring, in the (radius, height) half-plane
  z_edge = R - Sqrt(R * R - r_edge * r_edge);
  Field[3] = MathEval;
  Field[3].F = Sprintf("min(%g, %g + %g * sqrt((sqrt(x*x + y*y) - %g)^2 + (min(z, %g - z) - %g)^2))",
                       h, h_edge, (h - h_edge) / w_edge, r_edge, 2 * R, z_edge);
  sizes() += {3};
EndIf
If (h_surf < h)
  // depth below the surface of the sphere centred at (0, 0, R)
  Field[4] = MathEval;
  Field[4].F = Sprintf("min(%g, %g + %g * max(0, %g - sqrt(x*x + y*y + (z - %g)^2)))",
                       h, h_surf, (h - h_surf) / w_surf, R, R);
  sizes() += {4};
EndIf
Field[5] = Min;
Field[5].FieldsList = {sizes()};
Background Field = 5;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeMax = h;
// Also optimise tets of quality below 0.5 (default 0.3): better worst elements at no extra cost.
// (HXT, Algorithm3D = 10, gives better quality still but is not deterministic on the quarter.)
Mesh.OptimizeThreshold = 0.5;

Physical Volume("aggregate") = {1};
Physical Surface("surface") = Surface{:};
Physical Point("pole_bottom") = {pb()};
Physical Point("pole_top") = {pt()};
Physical Point("equator_y") = {pe};
