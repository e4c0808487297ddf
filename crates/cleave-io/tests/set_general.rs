//! `*SET_NODE_GENERAL`: node sets built from rules (ALL, NODE, PART, SET and the D- forms that
//! take nodes out), in the order written, as ANSA and LS-PrePost write them.

use cleave_io::deck::parse_deck;

mod blocks;
use blocks::hex_block;

/// Two blocks of 2 x 1 x 1 hexahedra of 10 mm, part 1 (nodes from 1) and part 2 (nodes from
/// 101), sharing no nodes; `sets` are added, and node set 9 is the one under test.
fn deck(sets: &str) -> String {
    let (n1, e1) = hex_block(1, 1, 1, [2, 1, 1], 0.01, [0.0; 3]);
    let (n2, e2) = hex_block(101, 11, 2, [2, 1, 1], 0.01, [0.0, 0.0, 0.02]);
    format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-6\n*PART\na\n1, 1, 1\n*PART\nb\n2, 1, 1\n\
         *SECTION_SOLID\n1, 1\n*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*NODE\n{n1}{n2}\
         *ELEMENT_SOLID\n{e1}{e2}{sets}*END\n"
    )
}

/// The deck ids of node set 9, ascending.
fn set9(sets: &str) -> Vec<i64> {
    let m = parse_deck(&deck(sets), "s.k")
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let s = m.node_sets.iter().find(|s| s.id == 9).expect("set 9");
    let mut ids: Vec<i64> = s.nodes.iter().map(|&n| m.node_ids[n as usize]).collect();
    ids.sort();
    ids
}

#[test]
fn rules_apply_in_order() {
    let part2: Vec<i64> = (101..113).collect();
    // PART: the nodes of the part's elements (in fixed format, with a title)
    assert_eq!(
        set9("*SET_NODE_GENERAL_TITLE\nupper\n         9\nPART               2\n"),
        part2
    );
    // ALL, then take part 1 out
    assert_eq!(set9("*SET_NODE_GENERAL\n9\nALL\nDPART, 1\n"), part2);
    // NODE, then DNODE; and SET of a set defined before, with one node taken out
    assert_eq!(
        set9("*SET_NODE_GENERAL\n9\nNODE, 1, 2, 3, 105\nDNODE, 2\n"),
        vec![1, 3, 105]
    );
    assert_eq!(
        set9(
            "*SET_NODE_LIST\n4\n1, 2, 3\n*SET_NODE_GENERAL\n9\nSET, 4\nPART, 2\nDSET, 4\nNODE, 2\n"
        ),
        [vec![2], part2.clone()].concat()
    );
    // a set built by rules is a set like any other: an SPC on it
    let m = parse_deck(
        &deck("*SET_NODE_GENERAL\n9\nPART, 2\n*BOUNDARY_SPC_SET\n9, 0, 1, 1, 1\n"),
        "s.k",
    )
    .unwrap()
    .model;
    assert_eq!(m.spcs.len(), 12);
}

#[test]
fn what_it_cannot_read_is_named() {
    let cases = [
        ("*SET_NODE_GENERAL\n9\nBOX, 1\n", "'BOX' not supported"),
        ("*SET_NODE_GENERAL\n9\nPART\n", "PART names no ids"),
        ("*SET_NODE_GENERAL\n9\nPART, 3\n", "part 3 is not defined"),
        (
            "*SET_NODE_GENERAL\n9\nSET, 4\n*SET_NODE_LIST\n4\n1\n",
            "node set 4 is not defined before this one",
        ),
    ];
    for (sets, want) in cases {
        let e = parse_deck(&deck(sets), "s.k").unwrap_err().to_string();
        assert!(e.contains(want), "{sets}: {e}");
    }
}
