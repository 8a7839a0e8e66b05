"""Open a run's fields.xdmf with ParaView's own readers and check what ParaView sees (run with pvpython).

Usage: pvpython check_paraview.py RUN_DIR [READER ...]
READER is XDMFReader (legacy XDMF 2), Xdmf3ReaderS or Xdmf3ReaderT (XDMF 3); default all three.
Needs RUN_DIR/expect.json (written by examples/io_fields.rs). For every reader and time step:
the time values, the number of points and cells, VTK cell type 24 (VTK_QUADRATIC_TETRA) for every
cell, every mid-edge point at the middle of its VTK edge, the cell connectivity (GMSH order with
nodes 8 and 9 swapped), the point coordinates and every point/cell array, compared exactly.
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


def leaf(d):
    while d.IsA("vtkMultiBlockDataSet"):
        d = d.GetBlock(0)
    return d


def main():
    run_dir = os.path.abspath(sys.argv[1])  # the XDMF 3 reader needs an absolute path
    readers = sys.argv[2:] or ["XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT"]
    with open(os.path.join(run_dir, "expect.json")) as f:
        e = json.load(f)
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
                if d.GetCellType(c) != 24:
                    errors.append(f"{where}: cell {c} has VTK type {d.GetCellType(c)}, expected 24")
                cell = d.GetCell(c)
                ids = [cell.GetPointId(i) for i in range(cell.GetNumberOfPoints())]
                want = [e["topology_gmsh"][c][j] for j in GMSH_TO_VTK]
                if ids != want:
                    errors.append(f"{where}: cell {c} connectivity {ids}, expected {want}")
                    continue
                for j, (a, b) in enumerate(VTK_EDGES):
                    mid = [0.5 * (pts[ids[a]][x] + pts[ids[b]][x]) for x in range(3)]
                    if max(abs(pts[ids[4 + j]][x] - mid[x]) for x in range(3)) > 1e-12:
                        errors.append(f"{where}: cell {c} point {4 + j} not at the middle of VTK edge {(a, b)}")
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
    print(f"check_paraview: OK {run_dir} with {', '.join(readers)}: {len(e['time'])} steps")


if __name__ == "__main__":
    main()
