// Indentation block as an axisymmetric cylinder of radius W and height H: its meridian rectangle
// [0,W] x [0,H] in the plane y = 0 (x the radius r, z the axis), graded towards the top of the
// axis (0, H), where a tool indents it: size h_c within the distance d_c of that point, growing
// linearly to h at the distance d_c + w_c.
// Usage: gmsh -2 -order 2 -format msh41 -setnumber H 1000 -setnumber h_c 1 block_meridian.geo -o b.msh
// Groups: surface "block"; curves "top" (z = H), "bottom" (z = 0), "sides" (x = W), "axis" (x = 0);
// point "top_centre" (0, H).
SetFactory("Built-in");

DefineConstant[ H = 1000 ];        // block height
DefineConstant[ W = H ];           // block radius
DefineConstant[ h = H / 8 ];       // element size far from the contact
DefineConstant[ h_c = H / 200 ];   // element size at the contact
DefineConstant[ d_c = 20 * h_c ];  // radius of the finest region
DefineConstant[ w_c = 0.5 * H ];   // distance over which the size grows from h_c to h

Point(1) = {0, 0, 0};
Point(2) = {W, 0, 0};
Point(3) = {W, 0, H};
Point(4) = {0, 0, H};
Line(1) = {1, 2};   // bottom
Line(2) = {2, 3};   // sides
Line(3) = {3, 4};   // top, from the side to the axis
Line(4) = {4, 1};   // axis
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Field[1] = Distance;
Field[1].PointsList = {4};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_c;
Field[2].SizeMax = h;
Field[2].DistMin = d_c;
Field[2].DistMax = d_c + w_c;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Physical Surface("block") = {1};
Physical Curve("bottom") = {1};
Physical Curve("sides") = {2};
Physical Curve("top") = {3};
Physical Curve("axis") = {4};
Physical Point("top_centre") = {4};
