//! Tied contact (`cleave_core::tied`) from the deck to the solver: a patch test across a
//! non-matching interface, momentum and the slave nodes' place on the faces through a free
//! flight, and the cards cleave refuses.

use cleave_core::solver::Solver;
use cleave_io::deck::{parse_deck, DeckError};

mod blocks;
use blocks::hex_block;

/// A lower block of 4 x 4 x 2 hexahedra of side 10 mm (part 1, nodes and elements from 1) and
/// on it, not sharing its nodes, an upper block of 8 x 8 x 2 of 5 mm (part 2, from 1001), tied
/// by `tied` (the card after the keyword); `extra` is added to the deck.
fn two_blocks(tied: &str, extra: &str) -> String {
    let h = 0.01;
    let (n1, e1) = hex_block(1, 1, 1, [4, 4, 2], h, [0.0; 3]);
    let (n2, e2) = hex_block(1001, 1001, 2, [8, 8, 2], 0.5 * h, [0.0, 0.0, 2.0 * h]);
    format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n2.0e-5\n*PART\nlower\n1, 1, 1\n*PART\nupper\n2, 1, 1\n\
         *SECTION_SOLID\n1, 1\n*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*NODE\n{n1}{n2}\
         *ELEMENT_SOLID\n{e1}{e2}{tied}{extra}*END\n"
    )
}

/// The velocity gradient of the patch test (1/s).
const L: [[f64; 3]; 3] = [[10.0, 3.0, -2.0], [1.0, -5.0, 4.0], [2.0, 1.0, 7.0]];

fn lin(x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|j| L[i][j] * x[j]).sum())
}

/// Patch test: every node starts with the velocity of a homogeneous deformation `v = L x` and
/// the nodes of the outer surface keep it (prescribed), but for the tied slave nodes. Each
/// upper face lies inside one lower face (2 x 2 upper faces on each), where the lumped forces
/// of the slave nodes carried by the bilinear weights are the lower face's consistent ones, so
/// the free nodes (inside, and on the interface) feel no net force: every node keeps `L x0` to
/// 1e-9 of its size and every element of both meshes has the same stress (1e-9 of it), after
/// 100 steps of large straining.
#[test]
fn a_non_matching_tied_interface_passes_the_patch_test() {
    let base = two_blocks("*CONTACT_TIED_SURFACE_TO_SURFACE\n2, 1, 3, 3\n", "");
    let m0 = parse_deck(&base, "t.k").unwrap().model;
    // the outer surface: x or y at 0 or 40 mm, z at 0 or 30 mm; the slaves are the upper
    // block's nodes at z = 20 mm
    let on = |v: f64, a: f64| (v - a).abs() < 1e-9;
    // (a scale factor of 0 reads as 1: zero components take a curve of zeros)
    let mut motion =
        String::from("*DEFINE_CURVE\n9\n0., 1.\n1., 1.\n*DEFINE_CURVE\n8\n0., 0.\n1., 0.\n");
    let mut init = String::new();
    for (k, x) in m0.x0.iter().enumerate() {
        let id = m0.node_ids[k];
        let v = lin(*x);
        init += &format!(
            "*INITIAL_VELOCITY_NODE\n{id}, {}, {}, {}\n",
            v[0], v[1], v[2]
        );
        let slave = id > 1000 && on(x[2], 0.02);
        let outer = on(x[0], 0.0)
            || on(x[0], 0.04)
            || on(x[1], 0.0)
            || on(x[1], 0.04)
            || on(x[2], 0.0)
            || on(x[2], 0.03);
        if outer && !slave {
            motion += "*BOUNDARY_PRESCRIBED_MOTION_NODE\n";
            for (dof, vi) in v.iter().enumerate() {
                let (lcid, sf) = if *vi == 0.0 { (8, 1.0) } else { (9, *vi) };
                motion += &format!("{id}, {}, 0, {lcid}, {sf}\n", dof + 1);
            }
        }
    }
    let deck = two_blocks(
        "*CONTACT_TIED_SURFACE_TO_SURFACE\n2, 1, 3, 3\n",
        &format!("{init}{motion}"),
    );
    let d = parse_deck(&deck, "t.k").unwrap_or_else(|e| panic!("{e}"));
    let m = d.model;
    assert_eq!(m.tied.len(), 1);
    let mut s = Solver::new(&m).expect("setup");
    for _ in 0..100 {
        s.advance_to_half_step().expect("step");
        s.update_positions().expect("positions");
    }
    let v = s.velocities();
    let mut worst: f64 = 0.0;
    for k in 0..m.x0.len() {
        let want = lin(m.x0[k]);
        for i in 0..3 {
            worst = worst.max((v[k][i] - want[i]).abs());
        }
    }
    // 1e-9 of the largest velocity (0.45 m/s)
    assert!(
        worst < 1e-9 * 0.45,
        "a node left the homogeneous motion by {worst:e} m/s"
    );
    let s0 = s.state.stress[0];
    let size = s0.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    assert!(size > 1e6, "{s0:?}");
    for (e, se) in s.state.stress.iter().enumerate() {
        let d = (0..6).fold(0.0f64, |a, i| a.max((se[i] - s0[i]).abs()));
        assert!(
            d < 1e-9 * size,
            "element {} differs by {d:e}",
            m.elem_ids[e]
        );
    }
    eprintln!("patch test: velocity error {worst:e} m/s, stress {size:e} Pa");
}

/// The upper block, on a lower one of 3 x 3 (a mesh of another pitch, faces straddling), is
/// thrown up at 2 m/s while the lower one rests: tied, they move on together. The momentum
/// (slave masses carried by the faces' nodes) stays the initial one to 1e-12, and every slave
/// node stays on its face: its position is the face's bilinear point, to 1e-12 of the size.
#[test]
fn tied_blocks_keep_their_momentum_and_their_slaves_on_the_faces() {
    let h = 0.01;
    let (n1, e1) = hex_block(1, 1, 1, [3, 3, 1], 4.0 * h / 3.0, [0.0; 3]);
    let (n2, e2) = hex_block(1001, 1001, 2, [8, 8, 2], 0.5 * h, [0.0, 0.0, 4.0 * h / 3.0]);
    let deck = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n4.0e-5\n*PART\nlower\n1, 1, 1\n*PART\nupper\n2, 1, 1\n\
         *SECTION_SOLID\n1, 1\n*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*NODE\n{n1}{n2}\
         *ELEMENT_SOLID\n{e1}{e2}*SET_PART_LIST\n5\n2\n*INITIAL_VELOCITY_GENERATION\n5, 1, 0., 0., 0., 2.\n\
         0., 0., 0., 0., 0., 1.\n\
         *SET_NODE_LIST_GENERATE\n7\n1001, 1081\n*CONTACT_TIED_NODES_TO_SURFACE\n7, 1, 4, 3\n*END\n"
    );
    let m = parse_deck(&deck, "t.k")
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let ties = cleave_core::tied::Ties::new(&m).unwrap();
    // the 81 nodes of the upper block's bottom, of 1001..1081
    assert_eq!(ties.ties.len(), 81, "{:?}", ties.untied);
    let mut s = Solver::new(&m).expect("setup");
    let p0 = s.momentum();
    assert!(p0[2] > 0.0);
    let mut steps = 0;
    while !s.is_finished() {
        s.advance_to_half_step().expect("step");
        s.update_positions().expect("positions");
        steps += 1;
    }
    let p = s.momentum();
    for i in 0..3 {
        assert!(
            (p[i] - p0[i]).abs() < 1e-12 * p0[2],
            "momentum {p:?} from {p0:?}"
        );
    }
    let x = s.positions();
    for t in &ties.ties {
        let at = (0..4).fold([0.0; 3], |a, k| {
            let q = x[t.masters[k] as usize];
            std::array::from_fn(|i| a[i] + t.weights[k] * q[i])
        });
        let xs = x[t.slave as usize];
        for i in 0..3 {
            assert!((xs[i] - at[i]).abs() < 1e-12 * 0.04, "slave off its face");
        }
    }
    // the blocks moved as one: the lower block's top rose with the upper one
    let top_lower = (0..m.x0.len())
        .filter(|&k| m.node_ids[k] < 1000 && m.x0[k][2] > 0.0)
        .map(|k| x[k][2] - m.x0[k][2])
        .sum::<f64>()
        / 16.0;
    assert!(top_lower > 1e-5, "{top_lower:e} after {steps} steps");
}

/// The deck writer keeps tied contacts (a surface and a node-set slave).
#[test]
fn tied_contacts_are_written_back() {
    for card in [
        "*CONTACT_TIED_SURFACE_TO_SURFACE\n2, 1, 3, 3\n",
        "*SET_NODE_LIST\n7\n1001, 1002\n*CONTACT_TIED_NODES_TO_SURFACE_ID\n4 glue\n7, 1, 4, 3\n",
    ] {
        let m = parse_deck(&two_blocks(card, ""), "t.k").unwrap().model;
        let back = parse_deck(&cleave_io::deck::write_deck(&m), "w.k")
            .unwrap()
            .model;
        assert_eq!(back.tied, m.tied);
        assert_eq!(m.tied.len(), 1);
    }
}

/// A slave node with an SPC, tied contact with separation, and unknown node sets are refused.
#[test]
fn refusals() {
    let err = |deck: &str| -> String {
        match parse_deck(deck, "t.k") {
            Err(e) => e.to_string(),
            Ok(d) => match Solver::new(&d.model) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("accepted: {deck}"),
            },
        }
    };
    let tied = "*CONTACT_TIED_SURFACE_TO_SURFACE\n2, 1, 3, 3\n";
    let e = err(&two_blocks(tied, "*BOUNDARY_SPC_NODE\n1041, 0, 1, 1, 1\n"));
    assert!(
        e.contains("node 1041 is a tied contact's slave node"),
        "{e}"
    );
    let e = err(&two_blocks(tied, "*MAT_ADD_SEPARATION\n1, 1, 1.0e8\n"));
    assert!(
        e.contains("tied contact in a deck with *MAT_ADD_SEPARATION"),
        "{e}"
    );
    let e = err(&two_blocks(
        "*CONTACT_TIED_NODES_TO_SURFACE\n99, 1, 4, 3\n",
        "",
    ));
    assert!(e.contains("node set 99 is not defined"), "{e}");
    let e: DeckError = parse_deck(
        &two_blocks("*CONTACT_TIED_SURFACE_TO_SURFACE_OFFSET\n2, 1, 3, 3\n", ""),
        "t.k",
    )
    .unwrap_err();
    assert!(e.to_string().contains("not supported"), "{e}");
}
