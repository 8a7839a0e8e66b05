// Meridian half-disc of the sphere of radius R centred at (0,0,R), for axisymmetric models: the
// plane y = 0, x >= 0, with x the radius r and z the axis (x^2 + (z - R)^2 <= R^2).
// Usage: gmsh -2 -order 2 -format msh41 -setnumber R 100 -setnumber h 25 sphere_meridian.geo -o m.msh
// Groups: surface "aggregate"; curves "surface" (the arc, two quarter circles meeting at the
// equator (R,0,R)), "axis" (x = 0, from z = 0 to z = 2R); points "pole_bottom" (0,0,0),
// "pole_top" (0,0,2R).
// Parameters and size fields as in sphere_quarter.geo, with r = x: the element size at a point
// (r, z) of the half-plane is the quarter's at the points of radius r and height z.
SetFactory("Built-in");

DefineConstant[ R = 100 ];          // sphere radius
DefineConstant[ h = R / 4 ];        // element size in the bulk
DefineConstant[ h_pole = h / 3 ];   // element size at the two poles (plate contacts)
DefineConstant[ r_pole = 0.5 * R ]; // distance over which the size blends from h_pole back to h
// Optional grading at the contact edges (off unless h_edge < h): size h_edge at the two points
// (r_edge, z_edge), (r_edge, 2R - z_edge) of the arc (where the contact patch ends at the peak
// force), growing linearly back to h over the distance w_edge.
DefineConstant[ h_edge = h ];
DefineConstant[ r_edge = 0.62 * R ];
DefineConstant[ w_edge = 0.25 * R ];
// Optional grading towards the whole arc (off unless h_surf < h): size h_surf on the surface,
// growing linearly to h over the depth w_surf (resolves the pressure layer under the drained
// surface, which the peak force depends on; docs/studies.md).
DefineConstant[ h_surf = h ];
DefineConstant[ w_surf = 0.3 * R ];

// Built-in circle arcs (exact circles: the order-2 mid-edge nodes lie on them) must span less
// than Pi, so the half circle is split at the equator. The centre (0,0,R) only defines the arcs:
// it bounds no curve and is in no group, so the .msh has no node for it (gmsh's logged node count
// includes it).
p0 = newp; Point(p0) = {0, 0, 0};
pc = newp; Point(pc) = {0, 0, R};
pq = newp; Point(pq) = {R, 0, R};
p1 = newp; Point(p1) = {0, 0, 2 * R};
c1 = newc; Circle(c1) = {p0, pc, pq};
c2 = newc; Circle(c2) = {pq, pc, p1};
ca = newc; Line(ca) = {p1, p0};
cl = newll; Curve Loop(cl) = {c1, c2, ca};
s = news; Plane Surface(s) = {cl};

eps = 1e-6 * R;
pb() = Point In BoundingBox{-eps, -eps, -eps, eps, eps, eps};
pt() = Point In BoundingBox{-eps, -eps, 2 * R - eps, eps, eps, 2 * R + eps};
axis() = Curve In BoundingBox{-eps, -eps, -eps, eps, eps, 2 * R + eps};
all() = Curve{:};
arc() = all();
arc() -= {axis()};
If (#pb() != 1 || #pt() != 1 || #axis() != 1 || #arc() != 2 || #all() != 3)
  Error("sphere_meridian.geo: unexpected topology (%g %g %g %g %g)", #pb(), #pt(), #axis(), #arc(), #all());
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
  // distance to the nearer of the two points, in the (radius, height) half-plane (y = 0 here)
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
// Frontal-Delaunay triangles (the default), then 5 smoothing passes: better worst triangles on
// the steeper gradings (h_edge), the same counts.
Mesh.Algorithm = 6;
Mesh.Smoothing = 5;

Physical Surface("aggregate") = {s};
Physical Curve("surface") = {arc()};
Physical Curve("axis") = {axis()};
Physical Point("pole_bottom") = {pb()};
Physical Point("pole_top") = {pt()};
