//! A lone hexahedron (one that shares no face with another element) takes the free-element
//! time step h / sqrt(3K/rho) from the start: at the usual h / c_L its uniform dilatation mode
//! (omega^2 = 12 K / (rho h^2), `material::free_element_speed`) is unstable, and a free block
//! falling under gravity rang up from round-off (internal energy from 1e-22 J to 41 J in 126
//! steps before this). Elements inside a mesh, also of a split mesh, keep h / c_L.

mod common;

use cleave_core::mesh::box_model;
use cleave_core::model::{BodyLoad, Material, MaterialKind};
use cleave_core::setup::Setup;

/// Soft rubber-like block material: rho 1000, E 1 MPa, nu 0.3.
fn soft() -> Material {
    Material {
        id: 1,
        density: 1000.0,
        young: 1e6,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

/// A 1 m block falling freely under gravity for 3 s stays unstrained: its internal and
/// hourglass energies stay at round-off (below 1e-9 J against 4e5 J of kinetic energy after
/// the fall; with the step h / c_L they grew to 41 J), its step the free-element one,
/// (c_L / sqrt(3K/rho)) = 0.73 of the usual for nu 0.3.
#[test]
fn a_lone_block_falling_freely_stays_unstrained() {
    let mut m = box_model([1, 1, 1], [1.0; 3], soft(), 3.0);
    m.body_loads.push(BodyLoad {
        axis: 2,
        curve: None,
        sf: 9.81,
    });
    let setup = Setup::new(&m).unwrap();
    assert_eq!(setup.lone, vec![true]);
    let mut steps = 0;
    let s = common::run(&m, |_| steps += 1);
    let e = s.state.energy;
    let c_l = {
        let (young, nu, rho): (f64, f64, f64) = (1e6, 0.3, 1000.0);
        (young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) / rho).sqrt()
    };
    let k = 1e6 / (3.0 * (1.0 - 2.0 * 0.3));
    let c_free = (3.0 * k / 1000.0_f64).sqrt();
    eprintln!(
        "lone block: {steps} steps, dt {:.4e} (h/c_L {:.4e}, h/c_free {:.4e}); KE {:.3e} J, IE {:.3e} J, HG {:.3e} J",
        s.state.dt_prev,
        1.0 / c_l,
        1.0 / c_free,
        e.kinetic,
        e.internal,
        e.hourglass
    );
    assert!(steps > 100, "{steps}");
    assert!(e.kinetic > 1.0, "it fell: {}", e.kinetic);
    assert!(e.internal.abs() < 1e-9 && e.hourglass.abs() < 1e-9, "{e:?}");
}

/// Which elements are lone: not those of a 2-element bar, nor those of a split mesh whose
/// faces are shared on the deck's nodes.
#[test]
fn only_elements_sharing_no_face_are_lone() {
    let bar = box_model([2, 1, 1], [2.0, 1.0, 1.0], soft(), 1e-3);
    assert_eq!(Setup::new(&bar).unwrap().lone, vec![false, false]);
    // two cubes touching along an edge only
    let mut two = box_model([1, 1, 1], [1.0; 3], soft(), 1e-3);
    let n0 = two.num_nodes() as u32;
    let far: Vec<_> = two
        .x0
        .iter()
        .map(|x| [x[0] + 1.0, x[1] + 1.0, x[2]])
        .collect();
    for x in far {
        two.x0.push(x);
        two.v0.push([0.0; 3]);
        two.node_ids.push(two.node_ids.len() as i64 + 1);
    }
    let c = two.conn[0].map(|n| n + n0);
    two.conn.push(c);
    two.elem_part.push(0);
    two.elem_ids.push(2);
    assert_eq!(Setup::new(&two).unwrap().lone, vec![true, true]);
    let mut split = bar.clone();
    split.separations.push(common::unbreakable(0));
    let sp = cleave_core::separation::split::split_model(&split);
    assert_eq!(Setup::new(&sp.model).unwrap().lone, vec![false, false]);
}
