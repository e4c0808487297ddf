//! What the GPU tests share: the device (or SKIPPED) and the block that uses every part of
//! the GPU step.
#![allow(dead_code)] // each test file uses its own subset

use cleave_core::curve::Curve;
use cleave_core::mesh::box_model;
use cleave_core::model::{
    BodyLoad, Hourglass, Material, MaterialKind, Model, MotionTarget, PrescribedMotion, Spc, Vad,
};
use cleave_gpu::Gpu;

/// The first device with f64 shaders, or `None` after saying SKIPPED.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => {
            eprintln!("GPU: {}", g.describe());
            Some(g)
        }
        Err(e) => {
            eprintln!("SKIPPED: {e}");
            None
        }
    }
}

/// A steel block 6 x 3 x 3 elements, bilinear plastic, hit on its top by a velocity that
/// ramps up (prescribed motion), clamped on its bottom (SPC), under a body load that ramps, with
/// an initial shear velocity: every part of the GPU step is used.
pub fn block(hourglass: Hourglass) -> Model {
    let steel = Material {
        id: 1,
        density: 7850.0,
        young: 210e9,
        poisson: 0.3,
        kind: MaterialKind::PlasticKinematic {
            sigy: 300e6,
            etan: 2e9,
            beta: 0.5,
        },
    };
    let mut m = box_model([3, 3, 6], [0.03, 0.03, 0.06], steel, 1.0);
    m.control.hourglass = hourglass;
    if hourglass == Hourglass::Stiffness {
        m.control.qh = 0.05;
    }
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 5e-6, 1.0],
        y: vec![0.0, 1.0, 1.0],
    });
    for (i, x) in m.x0.to_vec().iter().enumerate() {
        let n = i as u32;
        m.v0.as_mut_slice()[i] = [30.0 * x[2] / 0.06, 0.0, 0.0];
        if x[2] < 1e-9 {
            m.spcs.push(Spc {
                node: n,
                dof: [true, true, true, false, false, false],
            });
        } else if (x[2] - 0.06).abs() < 1e-9 {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(n),
                dof: cleave_core::model::MotionDof::Axis(2),
                vad: Vad::Velocity,
                curve: 0,
                sf: -40.0,
            });
        }
    }
    m.body_loads.push(BodyLoad {
        axis: 1,
        curve: Some(0),
        sf: 5e5,
    });
    let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
    m.control.end_time = 150.0 * dt * m.control.tssfac;
    m
}

/// A steel block (`n` x `n` x `n` elements, 4 mm on a side) at 300 m/s onto a steel plate (6 x 6 x
/// 3 elements of 2 mm, clamped at its rim) whose elements erode at a pressure of 2 GPa
/// (`*MAT_ADD_EROSION` MXPRES), to 10 us, without contact: the model and the block's material.
pub fn block_on_an_eroding_plate(name: &str, n: usize) -> (Model, usize) {
    use cleave_core::erosion::{ErosionDef, ErosionRule};
    use cleave_core::mesh::{Assembly, BoxMesh};
    let steel = Material {
        id: 0,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    };
    let mut a = Assembly::new(name, 1.0);
    let soft = a.material(steel.clone());
    let hard = a.material(steel);
    let plate = a.part("plate", soft);
    let block = a.part("block", hard);
    let mut p = BoxMesh::new([6, 6, 3], [0.012, 0.012, 0.006]);
    p.translate([0.0, 0.0, -0.006]);
    let (pn, _) = a.mesh(p, |_| plate);
    let mut b = BoxMesh::new([n, n, n], [0.004, 0.004, 0.004]);
    b.translate([0.00413, 0.00371, 1e-5]);
    let (bn, _) = a.mesh(b, |_| block);
    let mut m = a.finish();
    for i in bn {
        m.v0[i as usize] = [0.0, 0.0, -300.0];
    }
    for i in pn {
        let x = m.x0[i as usize];
        if x[0] < 1e-9 || x[0] > 0.012 - 1e-9 || x[1] < 1e-9 || x[1] > 0.012 - 1e-9 {
            m.spcs.push(Spc {
                node: i,
                dof: [true, true, true, false, false, false],
            });
        }
    }
    m.erosion = vec![ErosionDef {
        material: soft,
        rule: ErosionRule {
            max_pressure: Some(2e9),
            ncs: 1,
            ..Default::default()
        },
    }];
    m.control.end_time = 1.0e-5;
    (m, hard)
}
