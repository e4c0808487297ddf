//! `cleave example NAME`: write a ready deck for a bundled example.
//!
//! | name | what |
//! |---|---|
//! | `taylor-bar` | the classic copper Taylor impact test (LS-DYNA/NAFEMS benchmark): a cylinder of radius 3.2 mm and length 32.4 mm at 227 m/s onto a rigid wall, bilinear plasticity (E 117 GPa, nu 0.35, rho 8930 kg/m^3, SIGY 400 MPa, ETAN 100 MPa), 80 us. Published results: final length about 21.4-21.7 mm, foot radius about 7.0-7.1 mm. |

use std::path::PathBuf;

use cleave_core::mesh::{extrude, ogrid_disc, single_part_model};
use cleave_core::model::{Material, MaterialKind, Model, OutputRequests, RigidWall};

use crate::cli::ExampleArgs;
use crate::failure::Failure;

/// The bundled examples: name and one-line description.
pub const EXAMPLES: &[(&str, &str)] = &[(
    "taylor-bar",
    "copper Taylor bar, 227 m/s onto a rigid wall, bilinear plasticity (4320 elements, 80 us)",
)];

pub fn example(a: &ExampleArgs) -> Result<(), Failure> {
    let Some(name) = a.name.as_deref().filter(|_| !a.list) else {
        for (n, d) in EXAMPLES {
            println!("{n:<14} {d}");
        }
        return Ok(());
    };
    let mut model = match name {
        "taylor-bar" => taylor_bar(),
        other => {
            let names: Vec<&str> = EXAMPLES.iter().map(|e| e.0).collect();
            return Err(Failure::Input(format!(
                "unknown example '{other}'; available: {}",
                names.join(", ")
            )));
        }
    };
    if let Some(t) = a.end_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(Failure::Input(format!(
                "--end-time {t}: must be a positive number"
            )));
        }
        model.control.end_time = t;
    }
    if a.no_separation {
        model.separations.clear();
    }
    let path = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{name}.k")));
    std::fs::write(&path, cleave_io::deck::write_deck(&model))
        .map_err(|e| crate::failure::io_failure("cannot write", &path, e))?;
    println!(
        "wrote {} ({} elements, {} nodes); run it with: cleave run {}",
        path.display(),
        model.num_elements(),
        model.num_nodes(),
        path.display()
    );
    Ok(())
}

/// The Taylor bar: an O-grid cylinder (n = 6, m = 3: 108 elements per layer, 40 layers) along
/// z from 0 to L, moving at -227 m/s, with a stonewall at z = 0.
pub fn taylor_bar() -> Model {
    let (r, l) = (3.2e-3, 32.4e-3);
    let (pts, quads) = ogrid_disc(r, 6, 3);
    let mesh = extrude(&pts, &quads, l, 40);
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
    m.parts[0].title = "copper bar".into();
    m.v0.iter_mut().for_each(|v| *v = [0.0, 0.0, -227.0]);
    m.rigid_walls = vec![RigidWall {
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
