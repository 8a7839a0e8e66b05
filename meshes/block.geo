// Block [0,L] x [0,L] x [0,L] for homogeneous (0-D) verification states.
// Usage: gmsh -3 -order 2 -format msh41 -setnumber L 1 -setnumber h 1 block.geo -o block.msh
// Groups: volume "block"; surfaces "x0", "x1", "y0", "y1", "z0", "z1" (the faces x = 0, x = L, ...).
SetFactory("OpenCASCADE");

DefineConstant[ L = 1 ];   // edge length
DefineConstant[ h = L ];   // element size

Box(1) = {0, 0, 0, L, L, L};
MeshSize{ PointsOf{ Volume{1}; } } = h;

e = 1e-6 * L;
Physical Volume("block") = {1};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, L + e, L + e};
Physical Surface("x1") = Surface In BoundingBox{L - e, -e, -e, L + e, L + e, L + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, -e, L + e, e, L + e};
Physical Surface("y1") = Surface In BoundingBox{-e, L - e, -e, L + e, L + e, L + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, L + e, L + e, e};
Physical Surface("z1") = Surface In BoundingBox{-e, -e, L - e, L + e, L + e, L + e};
