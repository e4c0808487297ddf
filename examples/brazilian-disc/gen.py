"""Makes disc.msh, the mesh of brazilian-disc.k (run by hand, never by CI; CI has no Gmsh).

    python3 -m venv /tmp/g && /tmp/g/bin/pip install gmsh   # the PyPI wheel ships the library
    cd examples/brazilian-disc && /tmp/g/bin/python gen.py

The disc of a Brazilian test, D 50 mm, t 10 mm, in metres, lying in the x-y plane from z = 0 to
z = t, loaded along y: the loaded diameter is the plane x = 0. Its two ends are cut flat
(a "flattened Brazilian disc"): each flat spans a loading angle 2 ALPHA = 20 degrees of the rim,
at y = +/- R cos(ALPHA), half a width R sin(ALPHA) = 4.34 mm wide. The rigid platens of the deck
press on these flats, so the load is spread over 8.7 mm instead of a line a mesh cannot
resolve (the README of this folder says what a round disc did).

First-order tetrahedra (Gmsh type 4; cleave's ELFORM 10), sized by a background field that only
depends on the distance |x| to the loaded plane: H_FINE on it, growing linearly to H_COARSE at
|x| = BAND, so the crack's path along the diameter is resolved and the rest stays coarse. The
mesh is not aligned with the plane: no face lies on x = 0, and the crack has to find its way
through the tetrahedra.

Physical groups (cleave turns them into part and set ids, README "Gmsh meshes"):
- volume 1 "disc": the tetrahedra, part 1 of the deck;
- surface 2 "upper flat", surface 3 "lower flat": the flats, node and segment sets 2 and 3
  (not used by the deck, whose platens touch the disc through contact; there for a deck that
  would load the flats directly, e.g. *BOUNDARY_PRESCRIBED_MOTION_SET on node set 2).

Written as MSH 4.1 ASCII (diffable; Gmsh 4.15.2 wrote the committed file). The script prints
the counts, which the README of this folder quotes.
"""

import math

import gmsh

D = 0.05  # diameter (m)
T = 0.01  # thickness (m)
ALPHA = math.radians(10.0)  # half the loading angle of each flat
H_FINE = 1.5e-3  # element size on the loaded plane (m)
H_COARSE = 4.0e-3  # element size away from it (m)
BAND = 8.0e-3  # distance from the loaded plane over which the size grows (m)


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("brazilian-disc")
    occ = gmsh.model.occ
    r = D / 2
    y_flat = r * math.cos(ALPHA)
    cylinder = occ.addCylinder(0, 0, 0, 0, 0, T, r)
    slab = occ.addBox(-D, -y_flat, -T, 2 * D, 2 * y_flat, 3 * T)
    disc, _ = occ.intersect([(3, cylinder)], [(3, slab)])
    occ.synchronize()
    vol = disc[0][1]

    flats = {}
    for dim, tag in gmsh.model.getBoundary(disc, oriented=False):
        y0, y1 = gmsh.model.getBoundingBox(dim, tag)[1::3]
        if abs(y0 - y1) < 1e-6:  # (OCC pads bounding boxes by about 1e-7)
            flats["upper" if y0 > 0 else "lower"] = tag
    gmsh.model.addPhysicalGroup(3, [vol], 1, "disc")
    gmsh.model.addPhysicalGroup(2, [flats["upper"]], 2, "upper flat")
    gmsh.model.addPhysicalGroup(2, [flats["lower"]], 3, "lower flat")

    field = gmsh.model.mesh.field.add("MathEval")
    gmsh.model.mesh.field.setString(
        field, "F", f"{H_FINE} + {H_COARSE - H_FINE} * min(1, Fabs(x) / {BAND})"
    )
    gmsh.model.mesh.field.setAsBackgroundMesh(field)
    for option in ["MeshSizeFromPoints", "MeshSizeFromCurvature", "MeshSizeExtendFromBoundary"]:
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.optimize("Netgen")

    _, tets, _ = gmsh.model.mesh.getElements(3, vol)
    nodes, _, _ = gmsh.model.mesh.getNodes()
    gamma = gmsh.model.mesh.getElementQualities(tets[0], "gamma")
    volume = sum(gmsh.model.mesh.getElementQualities(tets[0], "volume"))
    exact = T * r * r * (math.pi - 2 * ALPHA + math.sin(2 * ALPHA))
    print(f"{len(tets[0])} tetrahedra, {len(nodes)} nodes, min gamma {min(gamma):.3f}")
    print(f"volume {volume:.6e} m^3 (exact {exact:.6e}), flats at y = +/-{y_flat:.10f} m")

    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write("disc.msh")
    gmsh.finalize()


if __name__ == "__main__":
    main()
