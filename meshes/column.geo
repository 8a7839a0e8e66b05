// Terzaghi consolidation column [0,W] x [0,W] x [0,H], structured tetrahedra
// (transfinite square base, extruded in layers, each prism split into 3 tets).
// Usage: gmsh -3 -order 2 -format msh41 -setnumber H 1 -setnumber h 0.05 column.geo -o column.msh
// Groups: volume "column"; surfaces "top" (z = H), "bottom" (z = 0), "sides" (the four lateral faces).
SetFactory("OpenCASCADE");

DefineConstant[ H = 1 ];          // column height
DefineConstant[ W = 0.1 * H ];    // column width (square cross-section)
DefineConstant[ h = W / 3 ];      // element size (in the cross-section and at the bottom)
DefineConstant[ h_top = h ];      // vertical element size at the top (drained face): grading h -> h_top

// Cross-section: n x n squares, each split into two triangles.
n = Ceil(W / h - 1e-9);
If (n < 1)
  n = 1;
EndIf
Rectangle(1) = {0, 0, 0, W, W};
Transfinite Curve{:} = n + 1;
Transfinite Surface{1} Alternated;

// Layers: the vertical size varies linearly from h (z = 0) to h_top (z = H).
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

out() = Extrude {0, 0, H} { Surface{1}; Layers{ ls(), zs() }; };

eps = 1e-6 * H;
top() = Surface In BoundingBox{-eps, -eps, H - eps, W + eps, W + eps, H + eps};
bottom() = Surface In BoundingBox{-eps, -eps, -eps, W + eps, W + eps, eps};
sides() = Surface{:};
sides() -= {top(), bottom()};
If (#top() != 1 || #bottom() != 1 || #sides() != 4)
  Error("column.geo: unexpected topology (%g %g %g)", #top(), #bottom(), #sides());
EndIf

Physical Volume("column") = {out(1)};
Physical Surface("top") = {top()};
Physical Surface("bottom") = {bottom()};
Physical Surface("sides") = {sides()};
