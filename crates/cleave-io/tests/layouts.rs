//! The three fixed-format layouts of LS-DYNA decks: standard, I10 (`*KEYWORD I10=Y`, `%`) and
//! long (`*KEYWORD LONG=Y`, `+`). One deck is written from the same values in each layout, the
//! field widths taken from the keyword manual and widened by the layout's rule, and in comma
//! format, which no layout changes: every fixed-layout deck must read as the comma deck does.

use std::path::{Path, PathBuf};

use cleave_io::deck::{parse_deck, read_deck, Deck};

/// How a deck's cards are written.
#[derive(Clone, Copy, PartialEq)]
enum Layout {
    Standard,
    I10,
    Long,
    /// Comma-separated.
    Free,
}

impl Layout {
    /// The width of a field whose standard width is `w` (PRIMER's manual, "Format: setting the
    /// file format": I10 widens fields under 10 to 10; long those under 20 to 20, 80-column
    /// text to 160, and keeps the 20-column ones).
    fn width(self, w: usize) -> usize {
        match self {
            Layout::Standard | Layout::Free => w,
            Layout::I10 => w.max(10),
            Layout::Long if w < 20 => 20,
            Layout::Long if w >= 80 => 2 * w,
            Layout::Long => w,
        }
    }
}

/// A field: its text, its standard width, and whether it is left-justified (text) or right.
type Field = (String, usize, bool);

fn num(v: impl ToString, w: usize) -> Field {
    (v.to_string(), w, false)
}

fn text(v: &str, w: usize) -> Field {
    (v.to_string(), w, true)
}

/// One data line in `layout`.
fn line(fields: &[Field], layout: Layout) -> String {
    if layout == Layout::Free {
        let v: Vec<&str> = fields.iter().map(|f| f.0.as_str()).collect();
        return v.join(", ") + "\n";
    }
    let mut s = String::new();
    for (v, w, left) in fields {
        let w = layout.width(*w);
        assert!(v.len() <= w, "{v} does not fit in {w} columns");
        if *left {
            s += &format!("{v:<w$}");
        } else {
            s += &format!("{v:>w$}");
        }
    }
    s.trim_end().to_string() + "\n"
}

/// A keyword with its lines; `sign` is written after its name (`+`, `%`, `-` or nothing).
struct Keyword {
    name: &'static str,
    lines: Vec<Vec<Field>>,
}

/// A 2 x 1 x 1 block of hexahedra of side 12.5 mm with node ids from `n0` and element ids from
/// `e0`, one element in each `*ELEMENT_SOLID` form, parameters in the material card, node 1
/// fixed by its TC, an SPC on a node set; every field in the manual's standard width.
fn model(n0: i64, e0: i64) -> Vec<Keyword> {
    let h = 0.0125;
    let mut nodes = Vec::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..3 {
                let id = n0 + i + 3 * j + 6 * k;
                let tc = if id == n0 { "7" } else { "" };
                nodes.push(vec![
                    num(id, 8),
                    num(format!("{:.6e}", h * i as f64), 16),
                    num(format!("{:.6e}", h * j as f64), 16),
                    num(format!("{:.6e}", h * k as f64), 16),
                    num(tc, 8),
                    num("", 8),
                ]);
            }
        }
    }
    let corners = |i: i64| -> Vec<i64> {
        [0, 1, 4, 3, 6, 7, 10, 9]
            .iter()
            .map(|&c| n0 + i + c)
            .collect()
    };
    let mut elements = vec![
        vec![num(e0, 8), num(1, 8)],
        corners(0).into_iter().map(|n| num(n, 8)).collect(),
    ];
    let mut one_card = vec![num(e0 + 1, 8), num(1, 8)];
    one_card.extend(corners(1).into_iter().map(|n| num(n, 8)));
    elements.push(one_card);
    vec![
        Keyword {
            name: "*PARAMETER",
            lines: vec![vec![text("R rho", 10), num("7850.", 10)]],
        },
        Keyword {
            name: "*PARAMETER_EXPRESSION",
            lines: vec![vec![text("R young", 10), text("2.0*1.05e11", 70)]],
        },
        Keyword {
            name: "*CONTROL_TERMINATION",
            lines: vec![vec![
                num("1.0e-6", 10),
                num(0, 10),
                num("0.0", 10),
                num("0.0", 10),
                num("1.0e8", 10),
            ]],
        },
        Keyword {
            name: "*PART",
            lines: vec![
                vec![text("the block", 80)],
                vec![num(1, 10), num(1, 10), num(1, 10)],
            ],
        },
        Keyword {
            name: "*SECTION_SOLID",
            lines: vec![vec![num(1, 10), num(2, 10)]],
        },
        Keyword {
            name: "*MAT_ELASTIC",
            lines: vec![vec![
                num(1, 10),
                num("&rho", 10),
                num("&young", 10),
                num("0.3", 10),
            ]],
        },
        Keyword {
            name: "*NODE",
            lines: nodes,
        },
        Keyword {
            name: "*ELEMENT_SOLID",
            lines: elements,
        },
        Keyword {
            name: "*SET_NODE_LIST",
            lines: vec![
                vec![num(5, 10)],
                vec![num(n0 + 2, 10), num(n0 + 5, 10), num(n0 + 8, 10)],
            ],
        },
        // a curve: its points are 20-column fields, which the long layout keeps
        Keyword {
            name: "*DEFINE_CURVE",
            lines: vec![
                vec![num(3, 10)],
                vec![num("0.0", 20), num("1.0", 20)],
                vec![num("1.0e-3", 20), num("2.5", 20)],
            ],
        },
        Keyword {
            name: "*BOUNDARY_SPC_SET",
            lines: vec![vec![
                num(5, 10),
                num(0, 10),
                num(1, 10),
                num(0, 10),
                num(1, 10),
            ]],
        },
    ]
}

/// The deck text: `*KEYWORD` with `options`, then each keyword in `layout_of(name)` with
/// `sign_of(name)` after its name.
fn deck(
    kws: &[Keyword],
    options: &str,
    layout_of: impl Fn(&str) -> Layout,
    sign_of: impl Fn(&str) -> &'static str,
) -> String {
    let mut s = format!("*KEYWORD {options}\n");
    for k in kws {
        s += &format!("{}{}\n", k.name, sign_of(k.name));
        for l in &k.lines {
            s += &line(l, layout_of(k.name));
        }
    }
    s + "*END\n"
}

fn read(text: &str) -> Deck {
    parse_deck(text, "layout.k").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// What the model read is: compared through its full debug print.
fn fingerprint(d: &Deck) -> String {
    format!("{:?}", d.model)
}

#[test]
fn every_layout_reads_as_the_comma_deck() {
    let kws = model(1, 1);
    let free = read(&deck(&kws, "", |_| Layout::Free, |_| ""));
    // the comma deck is the model meant: spot checks of what the layouts must agree on
    let m = &free.model;
    assert_eq!(m.node_ids.len(), 12);
    assert_eq!(m.elem_ids.len(), 2);
    assert_eq!(
        m.x0[m.node_ids.iter().position(|&n| n == 12).unwrap()][0],
        0.025
    );
    let want = fingerprint(&free);
    for (layout, options) in [
        (Layout::Standard, ""),
        (Layout::Standard, "100m LONG=S"),
        (Layout::I10, "I10=Y"),
        (Layout::I10, "i10=y"),
        (Layout::Long, "LONG=Y"),
        (Layout::Long, "long=y I10=Y"),
    ] {
        let d = read(&deck(&kws, options, |_| layout, |_| ""));
        assert_eq!(fingerprint(&d), want, "*KEYWORD {options}");
        assert_eq!(d.warnings, free.warnings);
    }
}

#[test]
fn a_sign_after_the_name_sets_one_keyword_layout() {
    let kws = model(1, 1);
    let want = fingerprint(&read(&deck(&kws, "", |_| Layout::Free, |_| "")));
    // a standard deck with the mesh long (`+`) and in I10 (`%`, written apart from the name)
    let layout = |k: &str| match k {
        "*NODE" => Layout::Long,
        "*ELEMENT_SOLID" => Layout::I10,
        _ => Layout::Standard,
    };
    let sign = |k: &str| match k {
        "*NODE" => "+",
        "*ELEMENT_SOLID" => " %",
        _ => "",
    };
    assert_eq!(fingerprint(&read(&deck(&kws, "", layout, sign))), want);
    // a long deck with the material and the part in the standard layout (`-`)
    let layout = |k: &str| match k {
        "*MAT_ELASTIC" | "*PART" => Layout::Standard,
        _ => Layout::Long,
    };
    let sign = |k: &str| match k {
        "*MAT_ELASTIC" | "*PART" => "-",
        _ => "",
    };
    assert_eq!(
        fingerprint(&read(&deck(&kws, "LONG=Y", layout, sign))),
        want
    );
    // the sign's keyword is the keyword without it (and the list of keywords read says so)
    let d = read(&deck(&kws, "LONG=Y", layout, sign));
    assert!(d.keywords.iter().any(|(k, _)| k == "*MAT_ELASTIC"));
}

/// Ids of 10 digits, the reason the I10 and long layouts exist, read the same in both; the
/// standard layout cannot hold them and says where.
#[test]
fn ten_digit_ids_in_the_wide_layouts() {
    let kws = model(4_000_000_001, 9_000_000_001);
    let free = read(&deck(&kws, "", |_| Layout::Free, |_| ""));
    assert!(free.model.node_ids.iter().any(|&n| n == 4_000_000_012));
    let want = fingerprint(&free);
    for (layout, options) in [(Layout::I10, "I10=Y"), (Layout::Long, "LONG=Y")] {
        let d = read(&deck(&kws, options, |_| layout, |_| ""));
        assert_eq!(fingerprint(&d), want, "{options}");
    }
    // 10 digits in the 8-column NID of the standard *NODE run into X
    let mut text = deck(&kws, "I10=Y", |_| Layout::I10, |_| "");
    text = text.replacen("*KEYWORD I10=Y", "*KEYWORD", 1);
    let e = parse_deck(&text, "layout.k").unwrap_err().to_string();
    assert!(
        e.contains("*NODE") && e.contains("runs across the edge"),
        "{e}"
    );
}

/// The layout of an included file: its own `*KEYWORD` line's, else its includer's.
#[test]
fn included_files_take_their_includer_layout() {
    let dir = scratch("includes");
    let kws = model(1, 1);
    let want = fingerprint(&read(&deck(&kws, "", |_| Layout::Free, |_| "")));
    let mesh = |layout: Layout| -> String {
        kws.iter()
            .filter(|k| matches!(k.name, "*NODE" | "*ELEMENT_SOLID"))
            .map(|k| {
                let mut s = format!("{}\n", k.name);
                for l in &k.lines {
                    s += &line(l, layout);
                }
                s
            })
            .collect()
    };
    let main = |options: &str, layout: Layout| -> String {
        let rest: Vec<Keyword> = model(1, 1)
            .into_iter()
            .filter(|k| !matches!(k.name, "*NODE" | "*ELEMENT_SOLID"))
            .collect();
        deck(&rest, options, |_| layout, |_| "").replace("*END\n", "*INCLUDE\nmesh.k\n*END\n")
    };
    // the mesh file has no *KEYWORD line: the long main deck makes it long
    std::fs::write(dir.join("mesh.k"), mesh(Layout::Long)).unwrap();
    assert_eq!(read_in(&dir, &main("LONG=Y", Layout::Long)), want);
    // its own *KEYWORD I10=Y holds inside a standard deck
    let own = format!("*KEYWORD I10=Y\n{}*END\n", mesh(Layout::I10));
    std::fs::write(dir.join("mesh.k"), own).unwrap();
    assert_eq!(read_in(&dir, &main("", Layout::Standard)), want);
}

#[test]
fn layout_errors_name_the_line() {
    let e = parse_deck("*KEYWORD LONG=Q\n*END\n", "k.k")
        .unwrap_err()
        .to_string();
    assert!(e.contains("k.k:1") && e.contains("LONG=Q"), "{e}");
    let e = parse_deck("*KEYWORD I10=maybe\n*END\n", "k.k")
        .unwrap_err()
        .to_string();
    assert!(e.contains("I10=MAYBE"), "{e}");
    // a long card with a value pushed 3 columns across its field's edge
    let kws = model(1, 1);
    let text = deck(&kws, "LONG=Y", |_| Layout::Long, |_| "").replacen(
        "                   2         1.250000e-2",
        "                   2            1.250000e-2",
        1,
    );
    let e = parse_deck(&text, "k.k").unwrap_err().to_string();
    assert!(
        e.contains("*NODE: field Y")
            && e.contains("columns 41-60")
            && e.contains("20 characters wide"),
        "{e}"
    );
    // a long deck without LONG=Y does not read (its first card, *PARAMETER's, has VAL1 in
    // columns 21-40, beyond the standard VAL1)
    let text = deck(&kws, "", |_| Layout::Long, |_| "");
    let e = parse_deck(&text, "k.k").unwrap_err().to_string();
    assert!(e.contains("k.k:3: *PARAMETER: field VAL1"), "{e}");
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("layouts-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn read_in(dir: &Path, main: &str) -> String {
    let p = dir.join("main.k");
    std::fs::write(&p, main).unwrap();
    fingerprint(&read_deck(&p).unwrap_or_else(|e| panic!("{e}")))
}
