"""Open a run's fields.xdmf with ParaView's own readers and check what ParaView sees (run with pvpython).

Usage: pvpython check_paraview.py RUN_DIR [READER ...]
READER is XDMFReader (legacy XDMF 2), Xdmf3ReaderS or Xdmf3ReaderT (XDMF 3); default all three.
Needs RUN_DIR/expect.json (written by tests/support/io_fields.rs, the io_fields example target);
its "family" ("Tet10" when absent) is the cell family:
  * Tet10 (10-node tetrahedra): VTK cell type 24 (VTK_QUADRATIC_TETRA), connectivity = GMSH
    Tetrahedron10 order with nodes 8 and 9 swapped, mid-edge points 4..9 on the VTK edges
    (0,1),(1,2),(0,2),(0,3),(1,3),(2,3);
  * Tri6 (6-node triangles of a meridian in the x-z plane): VTK cell type 22
    (VTK_QUADRATIC_TRIANGLE), connectivity = GMSH Triangle6 order unchanged, mid-edge points 3..5
    on the edges (0,1),(1,2),(2,0); points are still 3-D (y = 0) and vectors 3 components.
For every reader and time step: the time values, the number of points and cells, the VTK cell type
of every cell, every mid-edge point at the middle of its edge, the cell connectivity, the point
coordinates and every point/cell array, compared exactly.
A failing reader may abort pvpython (the XDMF 3 library throws uncaught C++ exceptions), so run one
reader per process if you need to tell them apart. Prints "check_paraview: OK ..." or errors and exits 1.
"""
import json
import os
import sys

from paraview import servermanager as sm
from paraview import simple

VTK_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
GMSH_TO_VTK = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
# Per family: VTK cell type, vertices per cell, VTK-order edges of the mid-edge points (point
# nv + k on edge k), and the GMSH -> VTK permutation (vtk[i] = gmsh[perm[i]]).
FAMILIES = {
    "Tet10": {"vtk_type": 24, "nv": 4, "edges": VTK_EDGES, "gmsh_to_vtk": GMSH_TO_VTK},
    "Tri6": {"vtk_type": 22, "nv": 3, "edges": [(0, 1), (1, 2), (2, 0)], "gmsh_to_vtk": [0, 1, 2, 3, 4, 5]},
}


def leaf(d):
    while d.IsA("vtkMultiBlockDataSet"):
        d = d.GetBlock(0)
    return d


def main():
    run_dir = os.path.abspath(sys.argv[1])  # the XDMF 3 reader needs an absolute path
    readers = sys.argv[2:] or ["XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT"]
    with open(os.path.join(run_dir, "expect.json")) as f:
        e = json.load(f)
    family = e.get("family", "Tet10")
    if family not in FAMILIES:
        print(f"check_paraview: ERROR: expect.json: unknown family {family!r}")
        sys.exit(1)
    fam = FAMILIES[family]
    if any(len(row) != len(fam["gmsh_to_vtk"]) for row in e["topology_gmsh"]):
        print(f"check_paraview: ERROR: expect.json: topology_gmsh rows must have {len(fam['gmsh_to_vtk'])} ids for {family}")
        sys.exit(1)
    fn = os.path.join(run_dir, "fields.xdmf")
    errors = []
    for rname in readers:
        if rname == "XDMFReader":
            r = simple.XDMFReader(FileNames=[fn])
        else:
            r = getattr(simple, rname)(FileName=[fn])
        r.UpdatePipelineInformation()
        tv = list(r.TimestepValues) if len(e["time"]) > 1 else [float(x) for x in (r.TimestepValues or [])]
        if len(e["time"]) > 1 and tv != e["time"]:
            errors.append(f"{rname}: time steps {tv}, expected {e['time']}")
        for k, t in enumerate(e["time"]):
            r.UpdatePipeline(t)
            d = leaf(sm.Fetch(r))
            where = f"{rname} step {k}"
            n, m = len(e["coordinates"]), len(e["topology_gmsh"])
            if d.GetNumberOfPoints() != n or d.GetNumberOfCells() != m:
                errors.append(f"{where}: {d.GetNumberOfPoints()} points, {d.GetNumberOfCells()} cells; expected {n}, {m}")
                continue
            pts = [list(d.GetPoint(i)) for i in range(n)]
            if pts != e["coordinates"]:
                errors.append(f"{where}: point coordinates differ")
            for c in range(m):
                if d.GetCellType(c) != fam["vtk_type"]:
                    errors.append(f"{where}: cell {c} has VTK type {d.GetCellType(c)}, expected {fam['vtk_type']}")
                cell = d.GetCell(c)
                ids = [cell.GetPointId(i) for i in range(cell.GetNumberOfPoints())]
                want = [e["topology_gmsh"][c][j] for j in fam["gmsh_to_vtk"]]
                if ids != want:
                    errors.append(f"{where}: cell {c} connectivity {ids}, expected {want}")
                    continue
                nv = fam["nv"]
                for j, (a, b) in enumerate(fam["edges"]):
                    mid = [0.5 * (pts[ids[a]][x] + pts[ids[b]][x]) for x in range(3)]
                    if max(abs(pts[ids[nv + j]][x] - mid[x]) for x in range(3)) > 1e-12:
                        errors.append(f"{where}: cell {c} point {nv + j} not at the middle of VTK edge {(a, b)}")
            for name, w in e["steps"][k].items():
                data = d.GetPointData() if w["kind"].startswith("Node") else d.GetCellData()
                arr = data.GetArray(name)
                if arr is None:
                    errors.append(f"{where}: array {name} missing")
                    continue
                got = [list(arr.GetTuple(i)) for i in range(arr.GetNumberOfTuples())]
                want = [v if isinstance(v, list) else [v] for v in w["values"]]
                if got != want:
                    errors.append(f"{where}: array {name} = {got}, expected {want}")
            names = {d.GetPointData().GetArrayName(i) for i in range(d.GetPointData().GetNumberOfArrays())}
            names |= {d.GetCellData().GetArrayName(i) for i in range(d.GetCellData().GetNumberOfArrays())}
            extra = names - set(e["steps"][k]) - {"vtkOriginalCellIds", "vtkOriginalPointIds"}
            if extra:
                errors.append(f"{where}: unexpected arrays {sorted(extra)}")
        simple.Delete(r)
    for x in errors:
        print("check_paraview: ERROR:", x)
    if errors:
        sys.exit(1)
    print(f"check_paraview: OK {run_dir} ({family}) with {', '.join(readers)}: {len(e['time'])} steps")


if __name__ == "__main__":
    main()
