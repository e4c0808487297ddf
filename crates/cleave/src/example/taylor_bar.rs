//! The copper Taylor bar (see the module table in [`super`]).

use cleave_core::element::Shape;
use cleave_core::mesh::{extrude, ogrid_disc, single_part_model};
use cleave_core::model::{Material, MaterialKind, Model, OutputRequests, RigidWall};

/// The Taylor bar: an O-grid cylinder (n = 6, m = 3: 108 elements per layer, 40 layers) along
/// z from 0 to L, moving at -227 m/s, with a stonewall at z = 0; on `shape`, each hexahedron
/// of that mesh cut into 2 wedges or 6 tetrahedra
/// ([`cleave_core::mesh::BoxMesh::split_wedges`], `split_tets`), with the section's `elform`
/// (1 for hexahedra and wedges; 10 or 13 for tetrahedra).
pub fn taylor_bar_of(shape: Shape, elform: i32) -> Model {
    let (r, l) = (3.2e-3, 32.4e-3);
    let (pts, quads) = ogrid_disc(r, 6, 3);
    let hexes = extrude(&pts, &quads, l, 40);
    let mesh = match shape {
        Shape::Hex => hexes,
        Shape::Wedge => hexes.split_wedges(),
        Shape::Tet => hexes.split_tets(),
    };
    let copper = Material {
        id: 1,
        density: 8930.0,
        young: 117e9,
        poisson: 0.35,
        kind: MaterialKind::PlasticKinematic {
            sigy: 400e6,
            etan: 100e6,
            beta: 1.0,
        },
    };
    let top_centre = mesh
        .x
        .iter()
        .position(|p| p[0] == 0.0 && p[1] == 0.0 && p[2] == l)
        .unwrap_or(0) as u32;
    let foot_edge = mesh
        .x
        .iter()
        .enumerate()
        .filter(|(_, p)| p[2] == 0.0)
        .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
        .map_or(0, |(i, _)| i as u32);
    let foot_centre_elem = mesh
        .conn
        .iter()
        .position(|c| {
            c.iter().any(|&n| {
                mesh.x[n as usize][2] == 0.0
                    && mesh.x[n as usize][0] == 0.0
                    && mesh.x[n as usize][1] == 0.0
            })
        })
        .unwrap_or(0) as u32;
    let mut m = single_part_model(mesh, copper, 80e-6);
    m.title = "Taylor bar: copper cylinder R 3.2 mm L 32.4 mm at 227 m/s onto a rigid wall".into();
    m.sections[0].elform = elform;
    let on = match (shape, elform) {
        (Shape::Hex, 1) => None,
        (Shape::Hex, _) => Some("hexahedra ELFORM 2"),
        (Shape::Wedge, _) => Some("wedges"),
        (Shape::Tet, 13) => Some("tetrahedra ELFORM 13"),
        (Shape::Tet, _) => Some("tetrahedra ELFORM 10"),
    };
    if let Some(on) = on {
        m.title = format!("Taylor bar, {on}: copper R 3.2 L 32.4 mm at 227 m/s, rigid wall");
    }
    m.parts[0].title = "copper bar".into();
    m.v0.iter_mut().for_each(|v| *v = [0.0, 0.0, -227.0]);
    m.rigid_walls = vec![RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        extent: None,
        id: 1,
        nodes: None,
        tail: [0.0; 3],
        head: [0.0, 0.0, 1.0],
        fric: 0.0,
    }];
    m.output = OutputRequests {
        glstat_dt: 0.5e-6,
        nodout_dt: 0.5e-6,
        elout_dt: 0.5e-6,
        rwforc_dt: 0.5e-6,
        rcforc_dt: 0.0,
        d3plot_dt: 4e-6,
        history_nodes: vec![top_centre, foot_edge],
        history_solids: vec![foot_centre_elem],
    };
    m
}
