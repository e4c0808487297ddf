//! `*INCLUDE_TRANSFORM` with `*DEFINE_TRANSFORMATION`: ids offset by class, nodes moved by
//! the composed map, mirrored elements reversed so that they run as their originals do, and
//! the cards cleave cannot transform refused by name.

use std::path::{Path, PathBuf};

use cleave_core::model::Model;
use cleave_core::solver::{Observer, Solver};
use cleave_io::deck::{read_deck, DeckError};

mod blocks;

/// A fresh scratch directory under the target directory.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("include-transform-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A block of 3 x 2 x 2 hexahedra of side `h` starting at x = `x0`: nodes 1.., elements 1..,
/// part 1 (section 1, elastic material 1), node set 1 holding every node, curve 7.
fn block(x0: f64, h: f64) -> String {
    let (nodes, elems) = blocks::hex_block(1, 1, 1, [3, 2, 2], h, [x0, 0.0, 0.0]);
    let mut t = format!("*KEYWORD\n*NODE\n{nodes}*ELEMENT_SOLID\n{elems}");
    t += "*PART\nblock\n1, 1, 1\n*SECTION_SOLID\n1, 1\n*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n";
    t += "*SET_NODE_LIST_GENERATE\n1\n1, 36\n*DEFINE_CURVE\n7\n0., 1.\n1., 1.\n*END\n";
    t
}

/// `*INCLUDE_TRANSFORM` of `file` with every offset `off` and TRANID `tranid` (0: none).
fn include_transform(file: &str, off: i64, tranid: i64) -> String {
    format!(
        "*INCLUDE_TRANSFORM\n{file}\n{off}, {off}, {off}, {off}, {off}, {off}, {off}\n{off}\n1.0, 1.0, 1.0\n{tranid}\n"
    )
}

fn read(dir: &Path, main: &str) -> Result<Model, DeckError> {
    let p = dir.join("main.k");
    std::fs::write(&p, main).unwrap();
    read_deck(&p).map(|d| d.model)
}

fn index(m: &Model, id: i64) -> usize {
    m.node_ids.iter().position(|&n| n == id).expect("node id")
}

/// Offsets and a translation, against the same block written out by hand with the ids raised
/// and the coordinates moved: the nodes, elements, parts and the set the offsets reach agree.
#[test]
fn offsets_and_translation_give_the_hand_made_model() {
    let d = scratch("transl");
    std::fs::write(d.join("block.k"), block(0.0, 0.01)).unwrap();
    let main = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-4\n*DEFINE_TRANSFORMATION\n5\nTRANSL, 0.5, -0.25, 2.0\n{}*INCLUDE\nblock.k\n*END\n",
        include_transform("block.k", 100, 5)
    );
    let m = read(&d, &main).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.node_ids.len(), 72);
    assert_eq!(m.elem_ids.len(), 24);
    for id in 1..=36 {
        let (a, b) = (m.x0[index(&m, id)], m.x0[index(&m, id + 100)]);
        let want = [a[0] + 0.5, a[1] - 0.25, a[2] + 2.0];
        assert!(
            (0..3).all(|i| (b[i] - want[i]).abs() < 1e-15),
            "node {id}: {b:?}, want {want:?}"
        );
    }
    // the hand-made copy: ids raised by 100 in every class, coordinates moved
    let moved: String = block(0.0, 0.01)
        .lines()
        .map(|l| l.to_string())
        .collect::<Vec<_>>()
        .join("\n");
    let mut hand = String::new();
    let mut kw = "";
    let mut card = 0;
    for l in moved.lines() {
        if l.starts_with('*') {
            kw = if l == "*KEYWORD" || l == "*END" {
                ""
            } else {
                l
            };
            card = 0;
            if !kw.is_empty() {
                hand += l;
                hand.push('\n');
            }
            continue;
        }
        card += 1;
        let f: Vec<&str> = l.split(", ").collect();
        let up = |s: &str| (s.parse::<i64>().unwrap() + 100).to_string();
        let line = match kw {
            "*NODE" => {
                let x: Vec<f64> = f[1..].iter().map(|v| v.parse().unwrap()).collect();
                format!(
                    "{}, {}, {}, {}",
                    up(f[0]),
                    x[0] + 0.5,
                    x[1] - 0.25,
                    x[2] + 2.0
                )
            }
            "*ELEMENT_SOLID" => f.iter().map(|v| up(v)).collect::<Vec<_>>().join(", "),
            "*PART" if card == 2 => f.iter().map(|v| up(v)).collect::<Vec<_>>().join(", "),
            "*SECTION_SOLID" | "*MAT_ELASTIC" => {
                let mut g: Vec<String> = f.iter().map(|v| v.to_string()).collect();
                g[0] = up(f[0]);
                g.join(", ")
            }
            "*SET_NODE_LIST_GENERATE" => f.iter().map(|v| up(v)).collect::<Vec<_>>().join(", "),
            "*DEFINE_CURVE" if card == 1 => up(f[0]),
            _ => l.to_string(),
        };
        hand += &line;
        hand.push('\n');
    }
    std::fs::write(d.join("hand.k"), format!("*KEYWORD\n{hand}*END\n")).unwrap();
    let h = read(
        &d,
        "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-4\n*INCLUDE\nblock.k\nhand.k\n*END\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(h.node_ids.len(), m.node_ids.len());
    for (k, &id) in h.node_ids.iter().enumerate() {
        let (a, b) = (h.x0[k], m.x0[index(&m, id)]);
        assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-15), "node {id}");
    }
    let by_id = |m: &Model, e: i64| {
        let k = m.elem_ids.iter().position(|&x| x == e).unwrap();
        (
            m.conn[k].map(|n| m.node_ids[n as usize]),
            m.parts[m.elem_part[k] as usize].id,
        )
    };
    for &e in &h.elem_ids {
        assert_eq!(by_id(&h, e), by_id(&m, e), "element {e}");
    }
    let ids = |m: &Model| {
        let mut v: Vec<i64> = m.parts.iter().map(|p| p.id).collect();
        v.sort();
        v
    };
    assert_eq!(ids(&m), vec![1, 101]);
    assert_eq!(ids(&h), ids(&m));
}

/// Records every node's position at the end.
struct Last(Vec<[f64; 3]>);
impl Observer for Last {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.0 = s.positions().iter().copied().collect();
        Ok(())
    }
}

/// A block and its mirror image (MIRROR about x = 0) hit two walls at x = 0 from either side
/// at 10 m/s and bounce off. A mirrored element keeps a positive volume only because its
/// connectivity is reversed; reversed, it runs as its original does, so the two blocks stay
/// each other's mirror images to round-off (1e-12 of the block's size) through the impact.
#[test]
fn a_mirrored_block_runs_as_the_mirror_image_of_its_original() {
    let d = scratch("mirror");
    std::fs::write(d.join("block.k"), block(0.005, 0.01)).unwrap();
    let main = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-3\n\
         *DEFINE_TRANSFORMATION\n9\nMIRROR, 0., 0., 0., -1., 0., 0.\n{}*INCLUDE\nblock.k\n\
         *RIGIDWALL_PLANAR\n1\n0., 0., 0., 1., 0., 0.\n*RIGIDWALL_PLANAR\n101\n0., 0., 0., -1., 0., 0.\n\
         *INITIAL_VELOCITY\n1\n-10., 0., 0.\n*INITIAL_VELOCITY\n101\n10., 0., 0.\n*END\n",
        include_transform("block.k", 100, 9)
    );
    let m = read(&d, &main).unwrap_or_else(|e| panic!("{e}"));
    let mut s = Solver::new(&m).expect("setup");
    let mut last = Last(Vec::new());
    s.run(&mut last).expect("run");
    let x = &last.0;
    // the blocks did hit their walls: the original's nodes moved back past their start
    let x1 = x[index(&m, 1)];
    assert!(x1[0] > 0.0 && s.state.t > 0.99e-3, "{x1:?}");
    let mut worst: f64 = 0.0;
    for id in 1..=36 {
        let (a, b) = (x[index(&m, id)], x[index(&m, id + 100)]);
        worst = worst
            .max((a[0] + b[0]).abs())
            .max((a[1] - b[1]).abs())
            .max((a[2] - b[2]).abs());
    }
    assert!(worst < 1e-12 * 0.03, "mirror images differ by {worst:e} m");
    let e = &s.state.energy;
    assert!(e.internal > 0.0, "no deformation: {e:?}");
}

/// What cleave cannot do inside a transformed include is refused naming the file, line,
/// keyword and why; so are unknown TRANIDs, unit conversion and unsupported options.
#[test]
fn refusals_name_the_card() {
    let d = scratch("refusals");
    std::fs::write(d.join("block.k"), block(0.0, 0.01)).unwrap();
    let head = "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-4\n*INCLUDE\nblock.k\n";
    let rot = "*DEFINE_TRANSFORMATION\n3\nROTATE, 0., 0., 1., 0., 0., 0., 30.\n";
    let cases: Vec<(String, &str, &str)> = vec![
        (
            format!("{head}{}*END\n", include_transform("block.k", 100, 4)),
            "main.k",
            "TRANID 4: no *DEFINE_TRANSFORMATION has this id",
        ),
        (
            format!(
                "{head}*INCLUDE_TRANSFORM\nblock.k\n100,100,100,100,100,100,100\n100\n1.0, 1.0, 25.4\n*END\n"
            ),
            "main.k",
            "field FCTLEN: 25.4: unit conversion of an included file is not supported",
        ),
        (
            format!(
                "{head}*DEFINE_TRANSFORMATION\n3\nPOS6N, 1., 2., 3., 4., 5., 6.\n{}*END\n",
                include_transform("block.k", 100, 3)
            ),
            "main.k",
            "option 'POS6N' not supported",
        ),
        (
            format!("{head}{rot}{}*END\n", include_transform("spc.k", 100, 3)),
            "spc.k",
            "*BOUNDARY_SPC_SET: not supported in a file read through *INCLUDE_TRANSFORM (its directions are not turned",
        ),
        (
            format!("{head}{}*END\n", include_transform("ctl.k", 100, 0)),
            "ctl.k",
            "*CONTROL_TIMESTEP: not supported in a file read through *INCLUDE_TRANSFORM (a global setting",
        ),
        (
            format!("{head}{}*END\n", include_transform("frame.k", 100, 0)),
            "frame.k",
            "*DEFINE_COORDINATE_SYSTEM: not supported in a file read through *INCLUDE_TRANSFORM (its points and ids are not moved and offset",
        ),
        (
            format!("{head}{}*END\n", include_transform("nested.k", 100, 0)),
            "nested.k",
            "an *INCLUDE_TRANSFORM inside a file read through another one is not supported",
        ),
    ];
    std::fs::write(
        d.join("spc.k"),
        block(0.0, 0.01).replace("*END", "*BOUNDARY_SPC_SET\n1, 0, 1, 0, 0\n*END"),
    )
    .unwrap();
    std::fs::write(
        d.join("ctl.k"),
        block(0.0, 0.01).replace("*END", "*CONTROL_TIMESTEP\n1.0e-7\n*END"),
    )
    .unwrap();
    std::fs::write(
        d.join("frame.k"),
        block(0.0, 0.01).replace(
            "*END",
            "*DEFINE_COORDINATE_SYSTEM\n5, 0., 0., 0., 1., 0., 0.\n0., 1., 0.\n*END",
        ),
    )
    .unwrap();
    std::fs::write(
        d.join("nested.k"),
        format!("*KEYWORD\n{}*END\n", include_transform("block.k", 5, 0)),
    )
    .unwrap();
    for (main, file, want) in cases {
        let e = read(&d, &main).expect_err(want);
        assert!(e.file.ends_with(file), "{e}");
        assert!(e.line.is_some(), "{e}");
        assert!(e.to_string().contains(want), "want '{want}' in: {e}");
    }
    // a translation leaves directions alone: the SPC is taken, its node set offset
    let ok = format!(
        "{head}*DEFINE_TRANSFORMATION\n3\nTRANSL, 1., 0., 0.\n{}*END\n",
        include_transform("spc.k", 100, 3)
    );
    let m = read(&d, &ok).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.node_ids.len(), 72);
}
