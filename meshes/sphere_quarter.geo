// Quarter x >= 0, y >= 0 of the sphere of radius R centred at (0,0,R) (symmetric loading).
// Usage: gmsh -3 -order 2 -format msh41 -setnumber R 100 -setnumber h 25 sphere_quarter.geo -o q.msh
// Groups: volume "aggregate"; surfaces "surface" (curved), "symmetry_x" (x = 0), "symmetry_y" (y = 0);
// points "pole_bottom" (0,0,0), "pole_top" (0,0,2R), "equator_y" (0,R,R) (off the axis, on the arc
// in x = 0: it locks the rotation about z of a full sphere mirrored from this quarter).
SetFactory("OpenCASCADE");

DefineConstant[ R = 100 ];          // sphere radius
DefineConstant[ h = R / 4 ];        // element size in the bulk
DefineConstant[ h_pole = h / 3 ];   // element size at the two poles (plate contacts)
DefineConstant[ r_pole = 0.5 * R ]; // distance over which the size blends from h_pole back to h
// Optional grading at the contact edges (off unless h_edge < h): size h_edge on the two rings of
// reference radius r_edge on the surface (where the contact patch ends at the peak force), growing
// linearly back to h over the distance w_edge.
DefineConstant[ h_edge = h ];
DefineConstant[ r_edge = 0.62 * R ];
DefineConstant[ w_edge = 0.25 * R ];
// Optional grading towards the whole curved surface (off unless h_surf < h): size h_surf on the
// surface, growing linearly to h over the depth w_surf (resolves the pressure layer under the
// drained surface, which the peak force depends on; docs/studies.md).
DefineConstant[ h_surf = h ];
DefineConstant[ w_surf = 0.3 * R ];

Sphere(1) = {0, 0, R, R};
Box(2) = {0, 0, -R, 2 * R, 2 * R, 4 * R};
v() = BooleanIntersection{ Volume{1}; Delete; }{ Volume{2}; Delete; };
// Split the arc in x = 0 at (0, R, R) so that the point becomes a mesh node.
pe = newp;
Point(pe) = {0, R, R};
v() = BooleanFragments{ Volume{v()}; Delete; }{ Point{pe}; Delete; };

eps = 1e-6 * R;
pe() = Point In BoundingBox{-eps, R - eps, R - eps, eps, R + eps, R + eps};
pb() = Point In BoundingBox{-eps, -eps, -eps, eps, eps, eps};
pt() = Point In BoundingBox{-eps, -eps, 2 * R - eps, eps, eps, 2 * R + eps};
sx() = Surface In BoundingBox{-eps, -eps, -eps, eps, R + eps, 2 * R + eps};
sy() = Surface In BoundingBox{-eps, -eps, -eps, R + eps, eps, 2 * R + eps};
all() = Surface{:};
curved() = all();
curved() -= {sx(), sy()};
If (#pb() != 1 || #pt() != 1 || #sx() != 1 || #sy() != 1 || #curved() != 1 || #pe() != 1)
  Error("sphere_quarter.geo: unexpected topology (%g %g %g %g %g %g)", #pb(), #pt(), #sx(), #sy(), #curved(), #pe());
EndIf

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

Physical Volume("aggregate") = {v()};
Physical Surface("surface") = {curved()};
Physical Surface("symmetry_x") = {sx()};
Physical Surface("symmetry_y") = {sy()};
Physical Point("pole_bottom") = {pb()};
Physical Point("pole_top") = {pt()};
Physical Point("equator_y") = {pe()};
