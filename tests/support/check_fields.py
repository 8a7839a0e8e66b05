#!/usr/bin/env python3
"""Check a poroplast run's fields.h5 + fields.xdmf (written by src/io/fields/).

Usage: check_fields.py RUN_DIR [--steps K] [--expect expect.json] [--straight-edges]

The cell family is "family" of the --expect file ("Tet10" when absent), or without --expect the
width of /mesh/topology (10: Tet10, 6: Tri6):
  * Tet10: 10-node tetrahedra; XDMF topology Tetrahedron_10, /mesh/topology M x 10 in VTK order
    (GMSH Tetrahedron10 order with nodes 8 and 9 swapped); VTK edges (0,1),(1,2),(0,2),(0,3),(1,3),(2,3)
    carry the mid-edge nodes 4..9;
  * Tri6: 6-node triangles of an axisymmetric meridian in the x-z plane (every y = 0); XDMF topology
    Triangle_6, /mesh/topology M x 6 in GMSH Triangle6 order written unchanged (= VTK's
    quadratic-triangle order); edges (0,1),(1,2),(2,0) carry the mid-edge nodes 3..5.
Always checked:
  * fields.xdmf parses (xml.etree); no fields.xdmf.<pid>.tmp left behind;
  * its root grid is a Uniform mesh grid (no step yet) or a Temporal collection of Uniform grids,
    each with a Time, the family's topology (Tetrahedron_10 with NodesPerElement 10, or Triangle_6
    with NodesPerElement 6), an XYZ geometry and Scalar/Vector attributes centred on Node or Cell;
  * every DataItem is Format="HDF", names an existing dataset of fields.h5 whose shape equals the
    declared Dimensions and whose type matches NumberType/Precision; element/node counts agree;
  * fields.h5: /mesh/coordinates (N x 3, float64, finite; y = 0 for Tri6), /mesh/topology (M x 10
    or M x 6, int64, ids in [0, N), distinct ids within each cell, every node used), /time (one
    value per step grid, equal to the XDMF Time values, strictly increasing), every
    /fields/<name>/<kkkkkk> dataset referenced by step k of the XDMF; vector fields have 3
    components for both families.
Optional:
  --steps K          the number of steps must be K;
  --straight-edges   mid-edge nodes must sit at the middle of the family's VTK-order edges (above)
                     -- true for straight-sided meshes, and for Tet10 the test that the
                     GMSH -> VTK node reordering was applied;
  --expect FILE      JSON with "family" (optional), "coordinates", "topology_gmsh" (GMSH order,
                     rows of 10 or 6 ids), "time" and "steps": [{name: {"kind": ..., "values":
                     [...]}}]; all compared exactly (topology: GMSH order with nodes 8, 9 swapped
                     for Tet10, unchanged for Tri6).
Prints "check_fields: OK ..." and exits 0, or lists every problem found and exits 1.
"""
import argparse
import glob
import json
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

VTK_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
GMSH_TO_VTK = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
# Per family: XDMF TopologyType, nodes per cell, vertices per cell, VTK-order edges of the mid-edge
# nodes (node n_vertices + k on edge k), and the GMSH -> VTK permutation (vtk[i] = gmsh[perm[i]]).
FAMILIES = {
    "Tet10": {"topology": "Tetrahedron_10", "npe": 10, "nv": 4, "edges": VTK_EDGES, "gmsh_to_vtk": GMSH_TO_VTK},
    "Tri6": {"topology": "Triangle_6", "npe": 6, "nv": 3, "edges": [(0, 1), (1, 2), (2, 0)],
             "gmsh_to_vtk": [0, 1, 2, 3, 4, 5]},
}
FAMILY_OF_WIDTH = {f["npe"]: name for name, f in FAMILIES.items()}
DTYPES = {("Float", "8"): np.float64, ("Float", "4"): np.float32, ("Int", "8"): np.int64,
          ("Int", "4"): np.int32, ("UInt", "8"): np.uint64, ("UInt", "4"): np.uint32}


class Checker:
    def __init__(self, run_dir):
        self.dir = run_dir
        self.errors = []
        self.family = "Tet10"
        self.fam = FAMILIES["Tet10"]

    def err(self, msg):
        self.errors.append(msg)

    def data_item(self, elem, where, h5):
        """Check one DataItem; return (h5 path, numpy array) or None."""
        items = elem.findall("DataItem")
        if len(items) != 1:
            self.err(f"{where}: expected one DataItem, found {len(items)}")
            return None
        di = items[0]
        if di.get("Format") != "HDF":
            self.err(f"{where}: Format={di.get('Format')!r}, expected HDF")
            return None
        ref = (di.text or "").strip()
        fname, _, obj = ref.partition(":")
        if fname != "fields.h5" or not obj.startswith("/"):
            self.err(f"{where}: bad HDF reference {ref!r}")
            return None
        if not os.path.exists(os.path.join(self.dir, fname)):
            self.err(f"{where}: {fname} does not exist")
            return None
        if obj not in h5 or not isinstance(h5[obj], h5py.Dataset):
            self.err(f"{where}: dataset {obj} missing from {fname}")
            return None
        ds = h5[obj]
        try:
            dims = tuple(int(x) for x in di.get("Dimensions", "").split())
        except ValueError:
            self.err(f"{where}: bad Dimensions {di.get('Dimensions')!r}")
            return None
        if ds.shape != dims:
            self.err(f"{where}: {obj} has shape {ds.shape}, XDMF declares {dims}")
        key = (di.get("NumberType", "Float"), di.get("Precision", "4"))
        want = DTYPES.get(key)
        if want is None or ds.dtype != np.dtype(want):
            self.err(f"{where}: {obj} has dtype {ds.dtype}, XDMF declares {key}")
        return obj, ds[()]

    def grid(self, g, where, h5, n_nodes, n_cells, mesh="/mesh"):
        """Check one Uniform grid; return {attribute name: (h5 path, center, type)}."""
        if g.get("GridType", "Uniform") != "Uniform":
            self.err(f"{where}: GridType {g.get('GridType')!r}, expected Uniform")
        topo = g.findall("Topology")
        geo = g.findall("Geometry")
        if len(topo) != 1 or len(geo) != 1:
            self.err(f"{where}: needs one Topology and one Geometry")
            return {}
        t = topo[0]
        if t.get("TopologyType") != self.fam["topology"]:
            self.err(f"{where}: TopologyType {t.get('TopologyType')!r}, expected {self.fam['topology']}")
        if t.get("NodesPerElement") not in (None, str(self.fam["npe"])):
            self.err(f"{where}: NodesPerElement {t.get('NodesPerElement')!r}, expected {self.fam['npe']}")
        if t.get("NumberOfElements") != str(n_cells):
            self.err(f"{where}: NumberOfElements {t.get('NumberOfElements')!r}, mesh has {n_cells}")
        r = self.data_item(t, where + "/Topology", h5)
        if r and r[0] != f"{mesh}/topology":
            self.err(f"{where}: topology refers to {r[0]}, not {mesh}/topology")
        if geo[0].get("GeometryType") != "XYZ":
            self.err(f"{where}: GeometryType {geo[0].get('GeometryType')!r}, expected XYZ")
        r = self.data_item(geo[0], where + "/Geometry", h5)
        if r and r[0] != f"{mesh}/coordinates":
            self.err(f"{where}: geometry refers to {r[0]}, not {mesh}/coordinates")
        attrs = {}
        for a in g.findall("Attribute"):
            name = a.get("Name")
            aw = f"{where}/Attribute[{name}]"
            if not name or name in attrs:
                self.err(f"{aw}: missing or repeated name")
                continue
            center, atype = a.get("Center"), a.get("AttributeType", "Scalar")
            if center not in ("Node", "Cell") or atype not in ("Scalar", "Vector"):
                self.err(f"{aw}: Center={center!r} AttributeType={atype!r}")
                continue
            r = self.data_item(a, aw, h5)
            if not r:
                continue
            rows = n_nodes if center == "Node" else n_cells
            shape = (rows,) if atype == "Scalar" else (rows, 3)
            if r[1].shape != shape:
                self.err(f"{aw}: shape {r[1].shape}, expected {shape} for {atype} on {center}")
            attrs[name] = (r[0], center, atype, r[1])
        return attrs

    def run(self, args):
        xdmf_path = os.path.join(self.dir, "fields.xdmf")
        h5_path = os.path.join(self.dir, "fields.h5")
        if glob.glob(xdmf_path + ".*tmp"):
            self.err("fields.xdmf.<pid>.tmp left behind")
        try:
            root = ET.parse(xdmf_path).getroot()
        except (OSError, ET.ParseError) as e:
            self.err(f"cannot parse {xdmf_path}: {e}")
            return None
        h5 = h5py.File(h5_path, "r")
        if root.tag != "Xdmf":
            self.err(f"root element {root.tag!r}, expected Xdmf")
        # Mesh.
        xyz = h5["/mesh/coordinates"][()] if "/mesh/coordinates" in h5 else None
        topo = h5["/mesh/topology"][()] if "/mesh/topology" in h5 else None
        if xyz is None or topo is None:
            self.err("missing /mesh/coordinates or /mesh/topology")
            return None
        if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.dtype != np.float64:
            self.err(f"/mesh/coordinates: shape {xyz.shape} dtype {xyz.dtype}")
        expect = None
        if args.expect:
            with open(args.expect) as f:
                expect = json.load(f)
            self.family = expect.get("family", "Tet10")
        elif topo.ndim == 2 and topo.shape[1] in FAMILY_OF_WIDTH:
            self.family = FAMILY_OF_WIDTH[topo.shape[1]]
        if self.family not in FAMILIES:
            self.err(f"unknown family {self.family!r} (expected one of {sorted(FAMILIES)})")
            return None
        self.fam = FAMILIES[self.family]
        npe = self.fam["npe"]
        if topo.ndim != 2 or topo.shape[1] != npe or topo.dtype != np.int64:
            self.err(f"/mesh/topology: shape {topo.shape} dtype {topo.dtype}, expected M x {npe} int64 for {self.family}")
            return None
        n, m = xyz.shape[0], topo.shape[0]
        if not np.all(np.isfinite(xyz)):
            self.err("/mesh/coordinates has non-finite values")
        if self.family == "Tri6" and xyz.ndim == 2 and xyz.shape[1] == 3 and np.any(xyz[:, 1] != 0):
            self.err(f"/mesh/coordinates: {int((xyz[:, 1] != 0).sum())} nodes of the Tri6 meridian have y != 0")
        if topo.size and (topo.min() < 0 or topo.max() >= n):
            self.err(f"/mesh/topology ids outside [0, {n})")
            return None
        if any(len(set(row)) != npe for row in topo.tolist()):
            self.err("/mesh/topology: a cell repeats a node")
        used = np.zeros(n, bool)
        used[topo.ravel()] = True
        if not used.all():
            self.err(f"{int((~used).sum())} nodes belong to no cell")
        if args.straight_edges and n:
            nv = self.fam["nv"]
            for k, (a, b) in enumerate(self.fam["edges"]):
                mid = 0.5 * (xyz[topo[:, a]] + xyz[topo[:, b]])
                bad = np.abs(xyz[topo[:, nv + k]] - mid).max(axis=1) > 1e-12 * (1 + np.abs(mid).max())
                if bad.any():
                    self.err(f"node {nv + k} of {int(bad.sum())} cells is not at the middle of VTK edge {(a, b)}")
        # Grids.
        domains = root.findall("Domain")
        grids = domains[0].findall("Grid") if len(domains) == 1 else []
        if len(grids) != 1:
            self.err("expected one Domain with one Grid")
            return None
        top = grids[0]
        steps = []  # (time, attrs)
        if top.get("GridType") == "Collection":
            if top.get("CollectionType") != "Temporal":
                self.err(f"collection type {top.get('CollectionType')!r}, expected Temporal")
            for i, g in enumerate(top.findall("Grid")):
                tv = g.find("Time")
                try:
                    t = float(tv.get("Value"))
                except (AttributeError, TypeError, ValueError):
                    self.err(f"step grid {i}: missing or bad Time")
                    t = float("nan")
                # A resumed run on another rank count writes its numbering as /mesh_g (/step_mesh).
                g_mesh = int(h5["/step_mesh"][i]) if "/step_mesh" in h5 and i < len(h5["/step_mesh"]) else 0
                mesh = "/mesh" if g_mesh == 0 else f"/mesh_{g_mesh}"
                if mesh not in h5 or h5[mesh + "/coordinates"].shape != (n, 3):
                    self.err(f"step {i}: mesh group {mesh} missing or not {n} x 3")
                steps.append((t, self.grid(g, f"step {i}", h5, n, m, mesh)))
        else:
            self.grid(top, "mesh grid", h5, n, m)
        # Time and field datasets.
        times = h5["/time"][()] if "/time" in h5 else None
        if times is None or times.ndim != 1:
            self.err("missing or non-1-D /time")
        else:
            if len(times) != len(steps):
                self.err(f"/time has {len(times)} values, XDMF has {len(steps)} steps")
            elif not np.array_equal(times, [t for t, _ in steps]):
                self.err(f"/time {times.tolist()} differs from XDMF times {[t for t, _ in steps]}")
            if np.any(np.diff(times) <= 0):
                self.err(f"/time is not strictly increasing: {times.tolist()}")
        referenced = {a[0] for _, attrs in steps for a in attrs.values()}
        for i, (_, attrs) in enumerate(steps):
            for name, a in attrs.items():
                if a[0] != f"/fields/{name}/{i:06d}":
                    self.err(f"step {i}: attribute {name} refers to {a[0]}")
        stored = set()
        if "/fields" in h5:
            h5["/fields"].visititems(lambda p, o: stored.add("/fields/" + p) if isinstance(o, h5py.Dataset) else None)
        for p in sorted(stored - referenced):
            self.err(f"{p} is not referenced by the XDMF")
        if args.steps is not None and len(steps) != args.steps:
            self.err(f"{len(steps)} steps, expected {args.steps}")
        if expect is not None:
            self.expect(expect, xyz, topo, times, steps)
        h5.close()
        return n, m, len(steps), len(stored)

    def expect(self, e, xyz, topo, times, steps):
        if not np.array_equal(xyz, np.array(e["coordinates"], float).reshape(-1, 3)):
            self.err("coordinates differ from expected")
        npe = self.fam["npe"]
        rows = e["topology_gmsh"]
        gm = np.array(rows, np.int64).reshape(-1, npe) if all(len(r) == npe for r in rows) else None
        if gm is None:
            self.err(f"expect.json: topology_gmsh rows of {sorted({len(r) for r in rows})} ids, "
                     f"expected {npe} for {self.family}")
        elif self.family == "Tet10":
            if not np.array_equal(topo, gm[:, GMSH_TO_VTK]):
                self.err(f"topology differs from expected GMSH topology with nodes 8, 9 swapped:\n{topo}\nvs\n{gm}")
        elif not np.array_equal(topo, gm[:, self.fam["gmsh_to_vtk"]]):
            self.err(f"topology differs from expected GMSH {self.family} topology (written unchanged):\n{topo}\nvs\n{gm}")
        if times is not None and not np.array_equal(times, np.array(e["time"], float)):
            self.err(f"time {times.tolist()} differs from expected {e['time']}")
        if len(e["steps"]) != len(steps):
            self.err(f"{len(steps)} steps, expected {len(e['steps'])}")
        for i, (want, (_, attrs)) in enumerate(zip(e["steps"], steps)):
            if set(want) != set(attrs):
                self.err(f"step {i}: fields {sorted(attrs)}, expected {sorted(want)}")
            for name, w in want.items():
                if name not in attrs:
                    continue
                center = "Node" if w["kind"].startswith("Node") else "Cell"
                atype = "Vector" if w["kind"].endswith("Vector") else "Scalar"
                if attrs[name][1:3] != (center, atype):
                    self.err(f"step {i}: {name} is {attrs[name][1:3]}, expected {(center, atype)}")
                if not np.array_equal(attrs[name][3], np.array(w["values"], float)):
                    self.err(f"step {i}: values of {name} differ:\n{attrs[name][3]}\nvs\n{w['values']}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--steps", type=int)
    ap.add_argument("--expect")
    ap.add_argument("--straight-edges", action="store_true")
    args = ap.parse_args()
    c = Checker(args.run_dir)
    try:
        r = c.run(args)
    except Exception as e:  # a broken file must give a report, not only a traceback
        c.err(f"{type(e).__name__}: {e}")
        r = None
    if c.errors:
        for e in c.errors:
            print("check_fields: ERROR:", e)
        sys.exit(1)
    n, m, k, f = r
    print(f"check_fields: OK {args.run_dir}: {c.family}, {n} nodes, {m} cells, {k} steps, {f} field datasets")


if __name__ == "__main__":
    main()
