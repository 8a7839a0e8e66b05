// Terzaghi consolidation column as an axisymmetric cylinder of radius W and height H: its meridian
// rectangle [0,W] x [0,H] in the plane y = 0 (x the radius r, z the axis), structured triangles
// (n cells across, extruded in layers, each quadrilateral split into 2 triangles).
// Usage: gmsh -2 -order 2 -format msh41 -setnumber H 1 -setnumber h 0.05 column_meridian.geo -o column.msh
// Groups: surface "column"; curves "top" (z = H), "bottom" (z = 0), "sides" (x = W), "axis" (x = 0).
SetFactory("OpenCASCADE");

DefineConstant[ H = 1 ];          // column height
DefineConstant[ W = 0.1 * H ];    // column radius
DefineConstant[ h = W / 3 ];      // element size (across the radius and at the bottom)
DefineConstant[ h_top = h ];      // vertical element size at the top (drained face): grading h -> h_top

// Across the radius: n cells.
n = Ceil(W / h - 1e-9);
If (n < 1)
  n = 1;
EndIf
// The bottom line runs from x = W to x = 0, so that the extruded triangles are counter-clockwise in
// (x, z), as in sphere_meridian.geo.
Point(1) = {W, 0, 0};
Point(2) = {0, 0, 0};
Line(1) = {1, 2};
Transfinite Curve{1} = n + 1;

// Layers: the vertical size varies linearly from h (z = 0) to h_top (z = H), as in column.geo.
// With s(z) = h + a z, the layer boundaries are equally spaced in t = Log(1 + a z / h) / a.
a = (h_top - h) / H;
If (Fabs(a) * H < 1e-9 * h)
  nl = Ceil(H / h - 1e-9);
  For k In {1:nl}
    zs(k - 1) = k / nl;
  EndFor
Else
  T = Log(h_top / h) / a;
  nl = Ceil(T - 1e-9);
  For k In {1:nl}
    zs(k - 1) = (h / a) * (Exp(a * T * k / nl) - 1) / H;
  EndFor
EndIf
zs(nl - 1) = 1;
For k In {1:nl}
  ls(k - 1) = 1;
EndFor

out() = Extrude {0, 0, H} { Curve{1}; Layers{ ls(), zs() }; };

eps = 1e-6 * H;
top() = Curve In BoundingBox{-eps, -eps, H - eps, W + eps, eps, H + eps};
bottom() = Curve In BoundingBox{-eps, -eps, -eps, W + eps, eps, eps};
sides() = Curve In BoundingBox{W - eps, -eps, -eps, W + eps, eps, H + eps};
axis() = Curve In BoundingBox{-eps, -eps, -eps, eps, eps, H + eps};
If (#top() != 1 || #bottom() != 1 || #sides() != 1 || #axis() != 1 || #out() != 4)
  Error("column_meridian.geo: unexpected topology (%g %g %g %g %g)", #top(), #bottom(), #sides(), #axis(), #out());
EndIf

Physical Surface("column") = {out(1)};
Physical Curve("top") = {top()};
Physical Curve("bottom") = {bottom()};
Physical Curve("sides") = {sides()};
Physical Curve("axis") = {axis()};
// The bottom of the axis, for scenes that need a point group there (plates.anchor of a column
// under a plate).
Physical Point("axis_bottom") = {2};
