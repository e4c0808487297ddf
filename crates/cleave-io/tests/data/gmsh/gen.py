"""Makes the Gmsh fixtures of crates/cleave-io/tests/gmsh.rs (run by hand, never by CI).

    python3 -m venv /tmp/g && /tmp/g/bin/pip install gmsh   # the PyPI wheel ships the library
    cd crates/cleave-io/tests/data/gmsh && /tmp/g/bin/python gen.py

Four meshes of the box [0, 1] x [0, 0.8] x [0, 0.6] (volume 0.48; the mixed one an L in it), each written in the four
encodings cleave reads: MSH 4.1 ASCII and binary, MSH 2.2 ASCII and binary (options
Mesh.MshFileVersion and Mesh.Binary), as NAME-41a.msh, NAME-41b.msh, NAME-22a.msh, NAME-22b.msh:

- tet:   the box meshed with linear tetrahedra (mesh size 0.4 at the corners);
- hex:   the box transfinite 4 x 3 x 2 and recombined: 24 hexahedra;
- prism: the bottom rectangle triangulated and extruded in 2 layers: prisms;
- mixed: an L of three blocks 0.5 x 0.8 x 0.3 (volume 0.36), one physical volume each:
  x < 0.5, z < 0.3 hexahedra (a recombined rectangle extruded in layers), x > 0.5, z < 0.3
  prisms (a triangulated one extruded), x > 0.5, z > 0.3 tetrahedra on the prisms' top
  triangles (an unstructured volume on that surface).

Then every file is read back by Gmsh itself (gmsh.open, an independent reader) and what it finds
is written to expected.json: node count, element count per MSH element type, and for each
physical group its dimension, tag, name, node count and element count per type, and for each
physical volume the sum of Gmsh's own element volumes (getElementQualities "volume"). The
analytic areas and volumes of the physical groups are written beside them.
"""

import json

import gmsh

LX, LY, LZ = 1.0, 0.8, 0.6
ENCODINGS = {"41a": (4.1, 0), "41b": (4.1, 1), "22a": (2.2, 0), "22b": (2.2, 1)}


def box_surfaces(tol=1e-6):
    """The box faces by position: {"x0": tag, "x1": ..., "z1": tag}."""
    out = {}
    for dim, tag in gmsh.model.getEntities(2):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        for name, lo, hi, ref in [
            ("x0", x0, x1, 0.0), ("x1", x0, x1, LX),
            ("y0", y0, y1, 0.0), ("y1", y0, y1, LY),
            ("z0", z0, z1, 0.0), ("z1", z0, z1, LZ),
        ]:
            if abs(lo - ref) < tol and abs(hi - ref) < tol:
                out.setdefault(name, []).append(tag)
    return out


def tet():
    gmsh.model.occ.addBox(0, 0, 0, LX, LY, LZ)
    gmsh.model.occ.synchronize()
    s = box_surfaces()
    gmsh.model.addPhysicalGroup(3, [1], 7, "solid")
    gmsh.model.addPhysicalGroup(2, s["z0"], 11, "bottom")
    gmsh.model.addPhysicalGroup(2, s["z1"], 12, "top")
    # the edge along x at y = z = 0, and the corner at the origin
    edge = [t for d, t in gmsh.model.getEntities(1)
            if gmsh.model.getBoundingBox(d, t)[3] > 0.99
            and max(abs(v) for v in gmsh.model.getBoundingBox(d, t)[1:3] + gmsh.model.getBoundingBox(d, t)[4:6]) < 1e-6]
    gmsh.model.addPhysicalGroup(1, edge, 21, "x-edge")
    corner = [t for d, t in gmsh.model.getEntities(0)
              if max(abs(v) for v in gmsh.model.getValue(0, t, [])) < 1e-9]
    gmsh.model.addPhysicalGroup(0, corner, 31, "origin")
    gmsh.model.mesh.setSize(gmsh.model.getEntities(0), 0.4)
    gmsh.model.mesh.generate(3)
    return {"areas": {"11": LX * LY, "12": LX * LY}, "volumes": {"7": LX * LY * LZ}}


def hex_():
    gmsh.model.occ.addBox(0, 0, 0, LX, LY, LZ)
    gmsh.model.occ.synchronize()
    s = box_surfaces()
    for d, t in gmsh.model.getEntities(1):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(d, t)
        n = 5 if x1 - x0 > 0.5 else (4 if y1 - y0 > 0.5 else 3)
        gmsh.model.mesh.setTransfiniteCurve(t, n)
    for d, t in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(t)
        gmsh.model.mesh.setRecombine(2, t)
    gmsh.model.mesh.setTransfiniteVolume(1)
    gmsh.model.addPhysicalGroup(3, [1], 1, "block")
    gmsh.model.addPhysicalGroup(2, s["x0"], 2, "fixed")
    gmsh.model.addPhysicalGroup(2, s["x1"], 3, "loaded")
    tip = [t for d, t in gmsh.model.getEntities(0)
           if max(abs(a - b) for a, b in zip(gmsh.model.getValue(0, t, []), (LX, LY, LZ))) < 1e-9]
    gmsh.model.addPhysicalGroup(0, tip, 4, "tip")
    gmsh.model.mesh.generate(3)
    return {"areas": {"2": LY * LZ, "3": LY * LZ}, "volumes": {"1": LX * LY * LZ}}


def rectangle(x0, x1, lc):
    g = gmsh.model.geo
    p = [g.addPoint(x0, 0, 0, lc), g.addPoint(x1, 0, 0, lc), g.addPoint(x1, LY, 0, lc),
         g.addPoint(x0, LY, 0, lc)]
    lines = [g.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
    return g.addPlaneSurface([g.addCurveLoop(lines)])


def prism():
    g = gmsh.model.geo
    base = rectangle(0, LX, 0.35)
    out = g.extrude([(2, base)], 0, 0, LZ, numElements=[2], recombine=True)
    g.synchronize()
    top = out[0][1]
    vol = out[1][1]
    gmsh.model.addPhysicalGroup(3, [vol], 5, "wedges")
    gmsh.model.addPhysicalGroup(2, [base], 6, "bottom")
    gmsh.model.addPhysicalGroup(2, [top], 7, "top")
    gmsh.model.mesh.generate(3)
    return {"areas": {"6": LX * LY, "7": LX * LY}, "volumes": {"5": LX * LY * LZ}}


def mixed():
    g = gmsh.model.geo
    h = LZ / 2
    # two rectangles sharing the edge x = 0.5 (built point by point so that they share it)
    pts = [g.addPoint(x, y, 0, 0.3) for x, y in [(0, 0), (0.5, 0), (1, 0), (1, LY), (0.5, LY), (0, LY)]]
    ln = lambda a, b: g.addLine(pts[a], pts[b])
    l01, l12, l23, l34, l45, l50, l14 = ln(0, 1), ln(1, 2), ln(2, 3), ln(3, 4), ln(4, 5), ln(5, 0), ln(1, 4)
    left = g.addPlaneSurface([g.addCurveLoop([l01, l14, l45, l50])])
    right = g.addPlaneSurface([g.addCurveLoop([l12, l23, l34, -l14])])
    for c, n in [(l01, 3), (l45, 3), (l14, 4), (l50, 4)]:
        g.mesh.setTransfiniteCurve(c, n)
    g.mesh.setTransfiniteSurface(left)
    g.mesh.setRecombine(2, left)
    a = g.extrude([(2, left)], 0, 0, h, numElements=[2], recombine=True)
    b = g.extrude([(2, right)], 0, 0, h, numElements=[2], recombine=True)
    c = g.extrude([(2, b[0][1])], 0, 0, h)
    g.synchronize()
    gmsh.model.addPhysicalGroup(3, [a[1][1]], 1, "hex")
    gmsh.model.addPhysicalGroup(3, [b[1][1]], 2, "prism")
    gmsh.model.addPhysicalGroup(3, [c[1][1]], 3, "tet")
    gmsh.model.addPhysicalGroup(2, [left, right], 10, "bottom")
    gmsh.model.addPhysicalGroup(2, [a[0][1], c[0][1]], 11, "top")  # z = 0.3 and z = 0.6
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
    gmsh.model.mesh.generate(3)
    v = 0.5 * LY * h
    return {"areas": {"10": LX * LY, "11": LX * LY}, "volumes": {"1": v, "2": v, "3": v},
            "total_volume": 3 * v}


def read_back(path):
    """What Gmsh itself finds in `path`."""
    gmsh.clear()
    gmsh.open(path)
    tags, _, _ = gmsh.model.mesh.getNodes()
    types, etags, _ = gmsh.model.mesh.getElements()
    out = {
        "nodes": len(tags),
        "elements": {str(t): len(e) for t, e in zip(types, etags)},
        "groups": [],
    }
    for dim, ptag in gmsh.model.getPhysicalGroups():
        ntags, _ = gmsh.model.mesh.getNodesForPhysicalGroup(dim, ptag)
        counts = {}
        vol = 0.0
        for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
            ts, es, _ = gmsh.model.mesh.getElements(dim, ent)
            for t, e in zip(ts, es):
                counts[str(t)] = counts.get(str(t), 0) + len(e)
                if dim == 3:
                    vol += float(sum(gmsh.model.mesh.getElementQualities(e, "volume")))
        grp = {
            "dim": dim,
            "tag": ptag,
            "name": gmsh.model.getPhysicalName(dim, ptag),
            "nodes": len(ntags),
            "elements": counts,
        }
        if dim == 3:
            grp["gmsh_volume"] = vol
        out["groups"].append(grp)
    return out


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    expected = {"gmsh": gmsh.__version__, "box": [LX, LY, LZ], "meshes": {}}
    for name, build in [("tet", tet), ("hex", hex_), ("prism", prism), ("mixed", mixed)]:
        gmsh.clear()
        gmsh.model.add(name)
        exact = build()
        files = {}
        for enc, (version, binary) in ENCODINGS.items():
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.option.setNumber("Mesh.Binary", binary)
            gmsh.write(f"{name}-{enc}.msh")
        for enc in ENCODINGS:
            files[enc] = read_back(f"{name}-{enc}.msh")
        expected["meshes"][name] = {"exact": exact, "files": files}
    gmsh.finalize()
    with open("expected.json", "w") as f:
        json.dump(expected, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
