//! `*CONTACT_AUTOMATIC_NODES_TO_SURFACE` with a node set as its slave side (SSTYP 4): the set's
//! nodes on exterior faces all of whose nodes it holds are checked, as the same contact with
//! the part as its slave side checks them; what it cannot check is said.

use cleave_core::contact::ContactSet;
use cleave_core::solver::{Observer, Solver};
use cleave_io::deck::parse_deck;

mod blocks;
use blocks::hex_block;

/// Records every node's position and velocity at the end.
#[derive(Default)]
struct Last(Vec<[f64; 3]>, Vec<[f64; 3]>);
impl Observer for Last {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.0 = s.positions().iter().copied().collect();
        self.1 = s.velocities().iter().copied().collect();
        Ok(())
    }
}

/// A plate of 4 x 4 x 1 hexahedra of 10 mm (part 1, nodes from 1) and, 0.1 mm above it, a block
/// of 2 x 2 x 2 (part 2, nodes from 1001) falling at 10 m/s; `contact` and `extra` added.
fn deck(contact: &str, extra: &str) -> String {
    let (n1, e1) = hex_block(1, 1, 1, [4, 4, 1], 0.01, [0.0; 3]);
    let (n2, e2) = hex_block(1001, 1001, 2, [2, 2, 2], 0.01, [0.01, 0.01, 0.0101]);
    format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n6.0e-5\n*PART\nplate\n1, 1, 1\n*PART\nblock\n2, 1, 1\n\
         *SECTION_SOLID\n1, 1\n*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*NODE\n{n1}{n2}\
         *ELEMENT_SOLID\n{e1}{e2}*INITIAL_VELOCITY_GENERATION\n2, 2, 0., 0., 0., -10.\n0., 0., 0., 0., 0., 0.\n\
         *CONTACT_AUTOMATIC_NODES_TO_SURFACE\n{contact}\n{extra}*END\n"
    )
}

fn run(text: &str) -> (Last, Vec<String>) {
    let d = parse_deck(text, "c.k").unwrap_or_else(|e| panic!("{e}"));
    let mut s = Solver::new(&d.model).unwrap();
    s.attach_contact(ContactSet::new(&d.model, None).expect("contact"));
    let mut last = Last::default();
    s.run(&mut last).unwrap();
    (last, d.warnings)
}

/// The block's 27 nodes as a node set run as the part does: it stops on the plate and turns
/// back (its nodes' mean velocity ends upward), and every node ends where the part's run puts
/// it (1e-12 of the block's size: the same nodes and faces checked, in another order).
#[test]
fn a_node_set_slave_is_the_surface_of_its_nodes() {
    let all: Vec<String> = (1001..1028).map(|n| n.to_string()).collect();
    let lines: Vec<String> = all.chunks(8).map(|c| c.join(", ")).collect();
    let set = format!("*SET_NODE_LIST\n5\n{}\n", lines.join("\n"));
    let (part, _) = run(&deck("2, 1, 3, 3", ""));
    let (nodes, warnings) = run(&deck("5, 1, 4, 3", &set));
    // the block's centre node lies on no exterior face
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("1 of node set 5's nodes")),
        "{warnings:?}"
    );
    let vz: f64 = part.1[50..].iter().map(|v| v[2]).sum::<f64>() / 27.0;

    assert!(vz > 0.0, "the block bounces: mean vz {vz}");
    let d = (part.0.iter().flatten().zip(nodes.0.iter().flatten()))
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(d <= 1e-12 * 0.02, "positions differ by {d:e}");
}

/// A set that holds the block's bottom face nodes only checks them (the same bounce), with a
/// warning naming the set's nodes it cannot check; one whose nodes span no exterior face is an
/// error naming the field.
#[test]
fn what_a_node_set_cannot_give_is_said() {
    // the bottom 9 nodes and one of the top layer
    let set = "*SET_NODE_LIST\n5\n1001, 1002, 1003, 1004, 1005, 1006, 1007, 1008\n1009, 1019\n";
    let (run_bottom, warnings) = run(&deck("5, 1, 4, 3", set));
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("1 of node set 5's nodes")),
        "{warnings:?}"
    );
    let vz: f64 = run_bottom.1[50..].iter().map(|v| v[2]).sum::<f64>() / 27.0;
    assert!(vz > 0.0, "the bottom nodes stop the block: mean vz {vz}");
    let e = parse_deck(
        &deck("5, 1, 4, 3", "*SET_NODE_LIST\n5\n1001, 1019\n"),
        "c.k",
    )
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("SSID"), "{e}");
    assert!(e.to_string().contains("no exterior face"), "{e}");
}
