//! Fuzzing the deck reader and the model build (issue 33, item 1): no deck, however
//! malformed, may make cleave panic, hang, or end "successfully" with non-finite figures.
//!
//! Each case takes one seed deck (the bundled examples `examples/taylor-bar.k` and
//! `examples/brazilian-disc/`, the decks `cleave example` writes, the test decks below),
//! applies one to six structured mutations drawn by a seeded generator (numbers replaced by
//! huge, tiny, negative, zero, NaN, inf, empty or text values, or scaled; ids changed to
//! undefined or repeated ones; cards dropped, duplicated, reordered or moved; keyword blocks
//! dropped, duplicated or moved; the file truncated; CRLF line ends, tabs, non-UTF-8 bytes,
//! a BOM; keywords misspelt), writes it to a file and runs it as `cleave run` does, in this
//! process: `read_deck`, the ParaView state cap, `split_model` when it has separation groups,
//! `Solver::new`, `attach_separation` / `attach_contact`, then at most 50 steps
//! (fewer on large meshes). A case fails on
//!
//! - a panic (`catch_unwind`), or any error with an empty message;
//! - a hang: a case that takes more than 10 s;
//! - steps that succeed with a non-finite energy, time step, position, velocity or stress.
//!
//! One case in [`BINARY_EVERY`] also runs the real binary, `cleave check` and
//! `cleave run --end-time T -q -o DIR` (T: the time the in-process run reached), and fails on
//! an exit code other than 0, 2 or 3 (101 is a panic, 1 a caught one or an I/O error here), a
//! run over 20 s, an exit 0 whose `glstat.csv` or `summary.json` holds a non-finite figure,
//! a deck `check` accepts (exit 0) and `run` refuses as bad input (exit 2), or an exit code
//! that disagrees with the in-process outcome (bad input there must be exit 2 with the same
//! message).
//!
//! Every case is reproducible from its number alone: case `n` draws its seed and mutations
//! from `splitmix64(n)`. A failure prints the case number, writes the mutated deck to
//! `$TMPDIR/cleave-fuzz-failures/case-N.k` and the test fails after the whole campaign,
//! listing every failure.
//!
//! The corpus `tests/fuzz-corpus/*.k` holds small mutated decks that once failed or that
//! exercise an error path worth keeping; [`fuzz_corpus_replays`] runs each of them, in
//! process and through the binary, every time. A corpus deck's first line says what it
//! exercises; a second line `$ expect: CODE TEXT` asks for exit code CODE and TEXT in the
//! error message (a regression test for a fixed defect).
//!
//! The default test runs [`DEFAULT_CASES`] cases (about half a minute in release mode on
//! two cores). A long campaign (the issue's aim is 10^5 cases without a defect):
//!
//! ```text
//! FUZZ_CASES=100000 nice -n 10 cargo test --release -p cleave --test fuzz -- fuzz_deck_mutations --nocapture
//! FUZZ_SECONDS=3600 FUZZ_START=100000 ...     # run for an hour, from case 100000 on
//! FUZZ_CASE=1234 ...                          # one case, its deck kept and its outcome shown
//! FUZZ_LOG=1 ...                              # every case's mutations and outcome on stderr
//! ```
//!
//! The solver runs in a rayon pool of one worker (`FUZZ_THREADS` to change it), so a campaign
//! leaves the other cores alone.

mod common;

use std::io::Read;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use cleave_core::contact::ContactSet;
use cleave_core::error::SolverError;
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::split_model;
use cleave_core::setup::estimate_time_step;
use cleave_core::solver::Solver;

/// Cases of the default test (`FUZZ_CASES` overrides it).
const DEFAULT_CASES: u64 = 4000;
/// One case in this many also runs the binary.
const BINARY_EVERY: u64 = 12;
/// The most steps a case runs in process.
const MAX_STEPS: u64 = 50;
/// A case's steps are cut so that steps x elements stays under this (large seeds).
const ELEMENT_STEPS: u64 = 150_000;
/// A case (in process) over this is a hang.
const CASE_LIMIT: Duration = Duration::from_secs(10);
/// A spawned `cleave` over this is a hang.
const BINARY_LIMIT: Duration = Duration::from_secs(20);
/// The most ParaView states `cleave run` writes (`run::MAX_STATES` of the binary).
const MAX_STATES: f64 = 10_000.0;

// ---------------------------------------------------------------------------------------
// The generator

/// splitmix64: a small, fast generator whose every state is a valid seed, so case `n` is
/// reproduced by `Rng(n)` alone.
#[derive(Clone, Debug)]
struct Rng(u64);

impl Rng {
    fn for_case(case: u64) -> Self {
        let mut r = Rng(case ^ 0x5eed_c1ea_7e00_0033);
        r.next();
        r
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (0 when n is 0).
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }

    fn chance(&mut self, p: f64) -> bool {
        ((self.next() >> 11) as f64) < p * (1u64 << 53) as f64
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

// ---------------------------------------------------------------------------------------
// Seeds

/// A seed deck: its text, the files it includes (written beside it), and how often it is
/// drawn relative to the others.
struct Seed {
    name: String,
    text: Vec<u8>,
    beside: Vec<(String, Vec<u8>)>,
    weight: u32,
}

/// What the fuzz seed adds to the reader test's deck of (nearly) every keyword
/// (`cleave-io/tests/all_keywords.k`: two elements, one elastic in a separation group, one
/// rigid): loads, rigid bodies of nodes, extra nodes and solid sets.
const ALL_KEYWORDS_EXTRA: &str = "\
*LOAD_NODE_POINT
12, 3, 2, 2.5
*LOAD_NODE_SET
1, 1, 2
*LOAD_SEGMENT
2, 5.0e6, 1.0e-4, 1, 2, 5, 4
2, 1.0e6, 0., 3, 6, 9, 9
*LOAD_SEGMENT_SET
3, 2, 2.0, 0.
*NODE
13, 5., 5., 5.
14, 6., 5., 5.
*NODE
15, 5., 6., 5.
16, 6., 6., 5.
17, 5., 6., 6.
*SET_NODE_LIST
9
15, 16, 17
*SET_NODE_LIST
11
13
*CONSTRAINED_NODAL_RIGID_BODY_INERTIA
50, , 9
5.5, 6., 5.5, 2.5, 0
1.0, 0.0, 0.0, 1.0, 0.0, 1.0
0.0, 0.0, -1.0, 0.0, 3.0, 0.0
*CONSTRAINED_EXTRA_NODES_NODE
2, 14, 1
*CONSTRAINED_EXTRA_NODES_SET
2, 11
*CONTROL_SOLID
1, 0, 0, 0, 0, 0.5
*SET_SOLID
20
2, 1
*SET_SOLID_GENERATE_TITLE
all
21
1, 2
*DATABASE_HISTORY_SOLID_SET
20
";

/// [`ALL_KEYWORDS_EXTRA`] put before the `*END` of the reader test's deck.
fn all_keywords() -> String {
    let base = include_str!("../../cleave-io/tests/all_keywords.k");
    let end = base.find("*END").expect("the deck ends with *END");
    format!("{}{ALL_KEYWORDS_EXTRA}{}", &base[..end], &base[end..])
}

/// Materials for the elastic bar of `common::BASE` (its `*MAT_ELASTIC` card replaced), so
/// that mutations reach every material's reader and update.
const MATERIALS: &[&str] = &[
    "*PARAMETER\nR rho      7800.\n*PARAMETER_EXPRESSION\nR e        2.0e11 * 1.5 / 1.5\n*MAT_PLASTIC_KINEMATIC\n1, &rho, &e, 0.3, 2.0e8, 1.0e9, 0.5",
    "*MAT_JOHNSON_COOK\n1, 7830., 8.18e10\n7.92e8, 5.1e8, 0.26, 0.014, 1.03, 1793., 294., 1.0\n477.\n*EOS_GRUNEISEN\n5, 4578., 1.33, 0., 0., 1.67, 0.43\n1.0",
    "*MAT_SIMPLIFIED_JOHNSON_COOK\n1, 7830., 2.0e11, 0.3\n7.92e8, 5.1e8, 0.26, 0.014, , , , 1.0",
    "*DEFINE_CURVE\n17, 0, 1., 1.0e6\n0., 250.\n0.1, 300.\n*MAT_PIECEWISE_LINEAR_PLASTICITY\n1, 7800., 2.0e11, 0.3, 1.0e8\n40.4, 5., 17",
    "*MAT_ELASTIC\n1,7800.0,2.0e11,0.3\n*MAT_ADD_SEPARATION\n1, 3, 1.0e6, 1.0, 100.0\n*INITIAL_VELOCITY\n\n1.0, 0., 0.",
    "*MAT_PIECEWISE_LINEAR_PLASTICITY\n1, 7800., 2.0e11, 0.3, 1.0e8, 1.0e9, 0.05\n*MAT_ADD_EROSION\n1, , 5.0e9, , , , , 1\n-1.0e8, 3.0e8, 4.0e8, 0.5, , , , 1.0e-3",
    "*MAT_JOHNSON_COOK\n1, 7830., 8.18e10, , 0.29\n7.92e8, 5.1e8, 0.26, 0.014, 1.03, 1793., 294., 1.0\n477., , , , 0.05, 3.44, -2.12, 0.002\n0.61, , 0, 1.0e-6",
    "*DEFINE_TABLE\n31, 1., 0.\n1.0\n100.\n*DEFINE_CURVE\n21\n0., 2.5e8\n0.1, 3.0e8\n*DEFINE_CURVE\n22\n0., 3.5e8\n0.1, 4.5e8\n*MAT_024\n1, 7800., 2.0e11, 0.3\n0., 0., 31",
];

/// What the tied and transformed-include seed adds to `common::BASE`: a block tied on the
/// bar's top, and a piece read through `*INCLUDE_TRANSFORM` (offsets, a translation and a
/// mirror).
const TIED_AND_TRANSFORMED: &str = "\
*PART
cap
2,1,1
*NODE
101,0.0,0.0,0.01
102,0.01,0.0,0.01
103,0.01,0.01,0.01
104,0.0,0.01,0.01
105,0.0,0.0,0.02
106,0.01,0.0,0.02
107,0.01,0.01,0.02
108,0.0,0.01,0.02
*ELEMENT_SOLID
101,2,101,102,103,104,105,106,107,108
*CONTACT_TIED_SURFACE_TO_SURFACE
2,1,3,3
*DEFINE_TRANSFORMATION
3
TRANSL,0.0,0.05,0.0
MIRROR,0.0,0.0,0.0,0.0,-1.0,0.0
*INCLUDE_TRANSFORM
piece.k
1000,1000,1000,1000,1000,1000,1000
1000
1.0,1.0,1.0
3
";

/// The file [`TIED_AND_TRANSFORMED`] includes.
const PIECE: &str = "*KEYWORD
*PART
piece
1,1,1
*SECTION_SOLID
1,1
*MAT_ELASTIC
1,2700.,7.0e10,0.33
*NODE
1,0.0,0.0,0.0
2,0.01,0.0,0.0
3,0.01,0.01,0.0
4,0.0,0.01,0.0
5,0.0,0.0,0.01
6,0.01,0.0,0.01
7,0.01,0.01,0.01
8,0.0,0.01,0.01
*ELEMENT_SOLID
1,1,1,2,3,4,5,6,7,8
*END
";

/// The seeds, in a fixed order (a case's number picks among them).
fn seeds(dir: &Path) -> Vec<Seed> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let read = |p: &str| std::fs::read(root.join(p)).unwrap_or_else(|e| panic!("{p}: {e}"));
    let text = |name: &str, t: String, weight| Seed {
        name: name.into(),
        text: t.into_bytes(),
        beside: Vec::new(),
        weight,
    };
    let mut out = vec![
        text("tests/common BASE", common::BASE.to_string(), 24),
        text("all keywords", all_keywords(), 24),
    ];
    for (i, m) in MATERIALS.iter().enumerate() {
        let old = "*MAT_ELASTIC\n1,7800.0,2.0e11,0.3";
        assert!(common::BASE.contains(old));
        let mut t = common::BASE.replacen(old, m, 1);
        if m.contains("*EOS_") {
            t = t.replacen("bar\n1,1,1\n", "bar\n1,1,1,5\n", 1);
        }
        out.push(text(&format!("BASE with material {}", i + 1), t, 5));
    }
    out.push(Seed {
        name: "BASE with a tied block and a transformed include".into(),
        text: common::BASE
            .replacen("*END", &format!("{TIED_AND_TRANSFORMED}*END"), 1)
            .into_bytes(),
        beside: vec![("piece.k".into(), PIECE.as_bytes().to_vec())],
        weight: 5,
    });
    out.push(Seed {
        name: "examples/brazilian-disc".into(),
        text: read("examples/brazilian-disc/brazilian-disc.k"),
        beside: vec![("disc.msh".into(), read("examples/brazilian-disc/disc.msh"))],
        weight: 3,
    });
    out.push(Seed {
        name: "examples/taylor-bar.k".into(),
        text: read("examples/taylor-bar.k"),
        beside: Vec::new(),
        weight: 1,
    });
    for (name, args, weight) in [
        ("fragmenting-bar", &["--elements", "24"][..], 8),
        (
            "ball-impact",
            &["--elements", "256", "--end-time", "2e-5"][..],
            3,
        ),
        ("three-point-bend", &["--end-time", "1e-6"][..], 1),
        (
            "taylor-bar",
            &["--shape", "tet13", "--end-time", "1e-6"][..],
            1,
        ),
    ] {
        let path = dir.join(format!("seed-{name}.k"));
        let p = path.to_str().unwrap();
        let mut a = vec!["example", name, "-o", p];
        a.extend_from_slice(args);
        let o = common::cleave(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out.push(Seed {
            name: format!("cleave example {name} {}", args.join(" ")),
            text: std::fs::read(&path).unwrap(),
            beside: Vec::new(),
            weight,
        });
    }
    out
}

// ---------------------------------------------------------------------------------------
// Mutations

/// Replacement values for a number or id field.
const VALUES: &[&str] = &[
    "1e300",
    "-1e300",
    "1.7976931348623157e308",
    "9e15",
    "9.1e15",
    "2147483648",
    "-2147483649",
    "99999",
    "1e-300",
    "5e-324",
    "1e-30",
    "0",
    "-0",
    "0.0",
    "-1",
    "-1e-9",
    "1",
    "2",
    "3",
    "7",
    "0.5",
    "1.5",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "Infinity",
    "1e999",
    "1d400",
    "",
    "abc",
    "1..2",
    "--1",
    "1e",
    "e5",
    "0x10",
    "1,2",
    "&nope",
    "-&nope",
    "\u{e9}",
];

/// Byte spans of the whitespace- or comma-separated tokens of a line.
fn tokens(line: &[u8]) -> Vec<(usize, usize)> {
    let sep = |b: u8| matches!(b, b' ' | b',' | b'\t' | b'\r');
    let mut out = Vec::new();
    let mut i = 0;
    while i < line.len() {
        if sep(line[i]) {
            i += 1;
            continue;
        }
        let s = i;
        while i < line.len() && !sep(line[i]) {
            i += 1;
        }
        out.push((s, i));
    }
    out
}

fn is_data(line: &[u8]) -> bool {
    !line.is_empty() && line[0] != b'*' && line[0] != b'$'
}

/// Line indices of the keyword lines (block starts).
fn blocks(lines: &[Vec<u8>]) -> Vec<usize> {
    (0..lines.len())
        .filter(|&i| lines[i].first() == Some(&b'*'))
        .collect()
}

/// The block (start, end) containing line `i`, or the block starting at the k-th keyword.
fn block_at(lines: &[Vec<u8>], k: usize) -> Option<(usize, usize)> {
    let b = blocks(lines);
    let s = *b.get(k)?;
    let e = b.get(k + 1).copied().unwrap_or(lines.len());
    Some((s, e))
}

/// A token of some data line of the deck: an id or a value used elsewhere.
fn some_token(rng: &mut Rng, lines: &[Vec<u8>]) -> Vec<u8> {
    for _ in 0..20 {
        let l = &lines[rng.below(lines.len())];
        if !is_data(l) {
            continue;
        }
        let t = tokens(l);
        if let Some(&(s, e)) = t.get(rng.below(t.len().min(3))) {
            return l[s..e].to_vec();
        }
    }
    b"1".to_vec()
}

/// Field `(s, e)` of `line` replaced by `new`, right-aligned in the field's columns when the
/// line is fixed format and it fits (so the other fields keep their columns).
fn replace_field(line: &[u8], (s, e): (usize, usize), new: &[u8]) -> Vec<u8> {
    let free = line.contains(&b',');
    let mut out = line[..s].to_vec();
    if !free
        && new.len()
            < e - s
                + (s - line[..s]
                    .iter()
                    .rposition(|&b| b != b' ')
                    .map_or(0, |p| p + 1))
    {
        // pad into the blanks before the field
        let start = line[..s]
            .iter()
            .rposition(|&b| b != b' ')
            .map_or(0, |p| p + 1);
        out.truncate(start);
        let width = e - start;
        out.extend(std::iter::repeat_n(b' ', width - new.len()));
        out.extend_from_slice(new);
    } else {
        out.extend_from_slice(new);
    }
    out.extend_from_slice(&line[e..]);
    out
}

/// One mutation of the deck's lines; returns what it did (for the log).
fn mutate(rng: &mut Rng, lines: &mut Vec<Vec<u8>>) -> String {
    if lines.is_empty() {
        lines.push(b"*KEYWORD".to_vec());
    }
    let data: Vec<usize> = (0..lines.len()).filter(|&i| is_data(&lines[i])).collect();
    let nb = blocks(lines).len();
    match rng.below(20) {
        // a field's value: 0-7 of 20, the most common
        0..=7 if !data.is_empty() => {
            let i = *rng.pick(&data);
            let t = tokens(&lines[i]);
            if t.is_empty() {
                return "nothing".into();
            }
            let f = t[rng.below(t.len())];
            let old = lines[i][f.0..f.1].to_vec();
            let new: Vec<u8> = match rng.below(6) {
                0 | 1 => rng.pick(VALUES).as_bytes().to_vec(),
                2 => some_token(rng, lines),
                3 => {
                    // scaled or negated
                    let v: f64 = String::from_utf8_lossy(&old).parse().unwrap_or(1.0);
                    let k = *rng.pick(&[-1.0, 1e6, 1e-6, 1e12, 1e-12, 0.5, 2.0, -1e-3]);
                    format!("{:e}", v * k).into_bytes()
                }
                4 => {
                    // an id one off, or far off
                    let v: i64 = String::from_utf8_lossy(&old).parse().unwrap_or(1);
                    let d = *rng.pick(&[1, -1, 2, 1000, -1000]);
                    v.saturating_add(d).to_string().into_bytes()
                }
                _ => {
                    // a digit changed
                    let mut o = old.clone();
                    let digits: Vec<usize> =
                        (0..o.len()).filter(|&k| o[k].is_ascii_digit()).collect();
                    if let Some(&k) = digits.get(rng.below(digits.len())) {
                        o[k] = b'0' + rng.below(10) as u8;
                    }
                    o
                }
            };
            lines[i] = replace_field(&lines[i], f, &new);
            format!(
                "line {}: '{}' -> '{}'",
                i + 1,
                String::from_utf8_lossy(&old),
                String::from_utf8_lossy(&new)
            )
        }
        8 if !data.is_empty() => {
            let i = *rng.pick(&data);
            lines.remove(i);
            format!("line {} dropped", i + 1)
        }
        9 if !data.is_empty() => {
            let i = *rng.pick(&data);
            let l = lines[i].clone();
            lines.insert(i, l);
            format!("line {} duplicated", i + 1)
        }
        10 if data.len() > 1 => {
            let i = *rng.pick(&data);
            let j = *rng.pick(&data);
            lines.swap(i, j);
            format!("lines {} and {} swapped", i + 1, j + 1)
        }
        11 if !data.is_empty() => {
            // a card moved into another place (often another keyword)
            let i = *rng.pick(&data);
            let l = lines.remove(i);
            let j = rng.below(lines.len() + 1);
            lines.insert(j, l);
            format!("line {} moved to {}", i + 1, j + 1)
        }
        12 if nb > 0 => {
            let (s, e) = block_at(lines, rng.below(nb)).unwrap();
            let what = String::from_utf8_lossy(&lines[s]).to_string();
            match rng.below(3) {
                0 => {
                    lines.drain(s..e);
                    format!("block {what} (line {}) dropped", s + 1)
                }
                1 => {
                    let b: Vec<Vec<u8>> = lines[s..e].to_vec();
                    let at = *rng.pick(&blocks(lines));
                    lines.splice(at..at, b);
                    format!(
                        "block {what} (line {}) duplicated at line {}",
                        s + 1,
                        at + 1
                    )
                }
                _ => {
                    let b: Vec<Vec<u8>> = lines.drain(s..e).collect();
                    let bl = blocks(lines);
                    let at = if bl.is_empty() { 0 } else { *rng.pick(&bl) };
                    lines.splice(at..at, b);
                    format!("block {what} (line {}) moved to line {}", s + 1, at + 1)
                }
            }
        }
        13 if nb > 0 => {
            // keyword misspelt, its case changed or an option added
            let b = blocks(lines);
            let i = *rng.pick(&b);
            let old = String::from_utf8_lossy(&lines[i]).to_string();
            let new = match rng.below(5) {
                0 => old.to_lowercase(),
                1 => format!("{old}_TITLE"),
                2 => format!("{old}_ID"),
                3 => old.replacen('*', "* ", 1),
                _ => old[..old.len().saturating_sub(1).max(1)].to_string(),
            };
            lines[i] = new.clone().into_bytes();
            format!("keyword line {}: {old} -> {new}", i + 1)
        }
        14 => {
            // truncated: a whole number of lines, or mid-line
            let n = rng.below(lines.len() + 1);
            lines.truncate(n);
            if let Some(l) = lines.last_mut() {
                if rng.chance(0.5) && !l.is_empty() {
                    let k = rng.below(l.len());
                    l.truncate(k);
                }
            }
            format!("truncated after line {n}")
        }
        15 => {
            let n = rng.below(lines.len());
            let l = &mut lines[n];
            let k = rng.below(l.len() + 1);
            let bytes: &[u8] = rng.pick::<&[u8]>(&[
                &[0xff][..],
                &[0xc3][..],
                &[0xe2, 0x82][..],
                &[0][..],
                b"\t",
                b"\r",
                b"\x0c",
                "\u{a0}".as_bytes(),
            ]);
            l.splice(k..k, bytes.iter().copied());
            format!("bytes {bytes:?} inserted in line {} at {k}", n + 1)
        }
        16 => {
            for l in lines.iter_mut() {
                l.push(b'\r');
            }
            "CRLF line ends".into()
        }
        17 if !data.is_empty() => {
            // spaces to tabs in a card (tabs are errors in fixed format, blanks in free)
            let i = *rng.pick(&data);
            let l = &mut lines[i];
            for b in l.iter_mut() {
                if *b == b' ' && rng.chance(0.3) {
                    *b = b'\t';
                }
            }
            format!("tabs in line {}", i + 1)
        }
        18 => {
            let i = rng.below(lines.len() + 1);
            let l: Vec<u8> = rng
                .pick(&[
                    "*INCLUDE\nnot-there.k",
                    "*KEYWORD",
                    "*END",
                    "*NOT_A_KEYWORD",
                    "*DATABASE_GLSTAT\n1e-30",
                    "*CONTROL_TERMINATION\n1e300",
                    "*CONTROL_TIMESTEP\n1e300, 10.",
                    "$ comment",
                    "",
                    ",,,,,,,,,,,,,,,,",
                    "*INCLUDE\ncase.k",
                ])
                .as_bytes()
                .to_vec();
            let n = l.split(|&b| b == b'\n').count();
            lines.splice(i..i, l.split(|&b| b == b'\n').map(<[u8]>::to_vec));
            format!("{n} line(s) inserted at line {}", i + 1)
        }
        _ => {
            lines.insert(0, vec![0xef, 0xbb, 0xbf]);
            if rng.chance(0.5) {
                let first = lines.remove(0);
                lines[0].splice(0..0, first);
            }
            "a byte-order mark".into()
        }
    }
}

// ---------------------------------------------------------------------------------------
// Running a deck

/// How a deck ended in process.
#[derive(Debug)]
enum Outcome {
    /// Refused by the reader or the model build (exit 2 for the binary), with the message.
    Input(String),
    /// A numerical failure within the steps run (exit 3).
    Numerical(String),
    /// Ran its steps (or to its end time) with finite figures; the time reached.
    Ran { steps: u64, t: f64 },
}

fn solver_outcome(e: SolverError) -> Outcome {
    if e.is_numerical() {
        Outcome::Numerical(e.to_string())
    } else {
        Outcome::Input(e.to_string())
    }
}

/// The deck at `path` read, built and stepped as `cleave run` does (see the module doc);
/// `Err` is a defect other than a panic (an empty message, a non-finite figure).
fn run_in_process(path: &Path) -> Result<Outcome, String> {
    let d = match cleave_io::deck::read_deck(path) {
        Ok(d) => d,
        Err(e) => {
            let m = e.to_string();
            if e.message.trim().is_empty() {
                return Err(format!("a deck error without a message: {m:?}"));
            }
            return Ok(Outcome::Input(m));
        }
    };
    let deck = d.model;
    let (dt, end) = (deck.output.d3plot_dt, deck.control.end_time);
    if dt > 0.0 && end / dt > MAX_STATES {
        return Ok(Outcome::Input(format!(
            "*DATABASE_BINARY_D3PLOT: DT {dt:e}"
        )));
    }
    let split = (!deck.separations.is_empty()).then(|| split_model(&deck));
    let model = split.as_ref().map_or(&deck, |s| &s.model);
    let mut solver = match Solver::new(model) {
        Ok(s) => s,
        Err(e) => return Ok(solver_outcome(e)),
    };
    if let Some(s) = &split {
        match Separation::from_parts(model, s.faces.clone(), s.interfaces) {
            Ok(sep) => solver.attach_separation(sep),
            Err(m) => return Ok(Outcome::Input(m)),
        }
    }
    if !model.contacts.is_empty() {
        match ContactSet::new(model, model.x0.origin()) {
            Ok(c) => solver.attach_contact(c),
            Err(m) => return Ok(Outcome::Input(m)),
        }
        let _ = solver.contact_time_step();
        let _ = estimate_time_step(model);
    }
    let ne = model.num_elements().max(1) as u64;
    let steps = MAX_STEPS.min((ELEMENT_STEPS / ne).max(3));
    for n in 0..steps {
        if let Err(e) = solver.advance_to_half_step() {
            return Ok(solver_outcome(e));
        }
        finite_state(&solver).map_err(|m| format!("step {n}, t = {:e}: {m}", solver.state.t))?;
        if solver.is_finished() {
            break;
        }
        if let Err(e) = solver.update_positions() {
            return Ok(solver_outcome(e));
        }
    }
    Ok(Outcome::Ran {
        steps: solver.state.step,
        t: solver.state.t,
    })
}

/// Every energy, the time and time step, and every position, velocity and stress finite.
fn finite_state(s: &Solver) -> Result<(), String> {
    let e = &s.state.energy;
    for (name, v) in [
        ("kinetic energy", e.kinetic),
        ("internal energy", e.internal),
        ("hourglass energy", e.hourglass),
        ("contact energy", e.contact),
        ("fracture energy", e.fracture),
        ("external work", e.external_work),
        ("initial energy", s.state.initial_energy),
        ("time", s.state.t),
        ("time step", s.state.dt),
    ] {
        if !v.is_finite() {
            return Err(format!("{name} is {v} after a step that succeeded"));
        }
    }
    let x = s.positions();
    let v = s.velocities();
    for i in 0..x.len() {
        if !x.get(i).iter().chain(v.get(i)).all(|c| c.is_finite()) {
            return Err(format!(
                "node index {i}: position {:?} velocity {:?} after a step that succeeded",
                x.get(i),
                v.get(i)
            ));
        }
    }
    if let Some(e) = s
        .state
        .stress
        .iter()
        .position(|t| !t.iter().all(|c| c.is_finite()))
    {
        return Err(format!("element index {e}: stress {:?}", s.state.stress[e]));
    }
    Ok(())
}

/// The text of a panic payload.
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

/// The in-process run of `path` in a thread of its own, in `pool`, with the watchdog.
fn run_guarded(pool: &Arc<rayon::ThreadPool>, path: &Path) -> Result<Outcome, String> {
    let p = path.to_path_buf();
    guarded(pool, CASE_LIMIT, move || run_in_process(&p))
}

/// `f` in a thread of its own, in `pool`: a panic is `Err("panic: ...")`, a result not back
/// within `limit` is `Err("hang: ...")` (the thread is left running: it cannot be stopped).
fn guarded(
    pool: &Arc<rayon::ThreadPool>,
    limit: Duration,
    f: impl FnOnce() -> Result<Outcome, String> + Send + 'static,
) -> Result<Outcome, String> {
    let (tx, rx) = mpsc::channel();
    let pool = pool.clone();
    std::thread::spawn(move || {
        let r = catch_unwind(AssertUnwindSafe(|| pool.install(f)));
        let _ = tx.send(r.unwrap_or_else(|e| Err(format!("panic: {}", panic_text(&*e)))));
    });
    match rx.recv_timeout(limit) {
        Ok(r) => r,
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!(
            "hang: no result in {:.1} s (the thread is left running)",
            limit.as_secs_f64()
        )),
        Err(mpsc::RecvTimeoutError::Disconnected) => Err("the case's thread died".into()),
    }
}

/// `cleave ARGS` with a time limit: exit code (`None`: killed by a signal) and stderr.
fn cleave_limited(args: &[&str]) -> Result<(Option<i32>, String), String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cleave"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start cleave: {e}"))?;
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = stderr.read_to_end(&mut s);
        String::from_utf8_lossy(&s).to_string()
    });
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            return Ok((status.code(), reader.join().unwrap_or_default()));
        }
        if start.elapsed() > BINARY_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "hang: cleave {} ran over {} s",
                args.join(" "),
                BINARY_LIMIT.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// `cleave check` and `cleave run` on the deck, against the in-process outcome.
fn run_binary(path: &Path, out: &Path, inproc: &Outcome) -> Result<(), String> {
    let p = path.to_str().unwrap();
    let (check, check_err) = cleave_limited(&["check", p])?;
    let end = match inproc {
        Outcome::Ran { t, .. } if *t > 0.0 => format!("{t:e}"),
        _ => "1e-7".into(),
    };
    let _ = std::fs::remove_dir_all(out);
    let o = out.to_str().unwrap();
    let (run, run_err) = cleave_limited(&[
        "run",
        p,
        "--end-time",
        &end,
        "-q",
        "--threads",
        "1",
        "-o",
        o,
    ])?;
    for (what, code, err) in [("check", check, &check_err), ("run", run, &run_err)] {
        match code {
            Some(0) => {}
            Some(2 | 3) => {
                let msg = err.lines().find(|l| l.starts_with("error: "));
                if msg.is_none_or(|m| m.trim().len() <= "error:".len()) {
                    return Err(format!(
                        "{what}: exit {code:?} without an error message: {err}"
                    ));
                }
            }
            _ => return Err(format!("{what}: exit {code:?}: {err}")),
        }
    }
    if check == Some(0) && run == Some(2) {
        return Err(format!("check accepts the deck, run refuses it: {run_err}"));
    }
    match inproc {
        Outcome::Input(m) => {
            // `check` sees the deck's own end time; `run` --end-time T, which may lift the
            // ParaView state cap
            let first = m.lines().next().unwrap_or("");
            let capped = first.starts_with("*DATABASE_BINARY_D3PLOT: DT");
            if check != Some(2)
                || !check_err.contains(first)
                || (!capped && (run != Some(2) || !run_err.contains(first)))
            {
                return Err(format!(
                    "in process: bad input ({m}); check: exit {check:?}: {check_err}; run: exit {run:?}: {run_err}"
                ));
            }
        }
        Outcome::Ran { .. } if run == Some(2) => {
            return Err(format!("in process: ran; run: exit 2: {run_err}"));
        }
        Outcome::Numerical(m) if run == Some(2) => {
            return Err(format!(
                "in process: a numerical failure ({m}); run: exit 2: {run_err}"
            ));
        }
        _ => {}
    }
    if run == Some(0) {
        finite_output(out)?;
    }
    Ok(())
}

/// After exit 0: every number of glstat.csv and summary.json's energy ratio finite.
fn finite_output(out: &Path) -> Result<(), String> {
    let g = std::fs::read_to_string(out.join("glstat.csv"))
        .map_err(|e| format!("exit 0 without glstat.csv: {e}"))?;
    for (k, line) in g.lines().enumerate().skip(1) {
        if line
            .split(',')
            .any(|v| !v.parse::<f64>().is_ok_and(f64::is_finite))
        {
            return Err(format!("exit 0 with glstat.csv row {k}: {line}"));
        }
    }
    let s = std::fs::read_to_string(out.join("summary.json"))
        .map_err(|e| format!("exit 0 without summary.json: {e}"))?;
    let j: serde_json::Value =
        serde_json::from_str(&s).map_err(|e| format!("summary.json: {e}: {s}"))?;
    if !j["energy_ratio"].as_f64().is_some_and(f64::is_finite) {
        return Err(format!("exit 0 with energy_ratio {}", j["energy_ratio"]));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// The campaign

/// A scratch folder and the rayon pool the cases share.
struct Bench {
    dir: common::Scratch,
    pool: Arc<rayon::ThreadPool>,
}

impl Bench {
    fn new(name: &str) -> Self {
        let threads = env_u64("FUZZ_THREADS").unwrap_or(1) as usize;
        Bench {
            dir: common::tmp(name),
            pool: Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap(),
            ),
        }
    }

    /// Runs one deck (in process, and through the binary when `binary`); `Err`: the defect.
    fn case(
        &self,
        text: &[u8],
        beside: &[(String, Vec<u8>)],
        binary: bool,
    ) -> (Result<Outcome, String>, PathBuf) {
        let path = self.dir.join("case.k");
        std::fs::write(&path, text).unwrap();
        for (name, bytes) in beside {
            std::fs::write(self.dir.join(name), bytes).unwrap();
        }
        let r = run_guarded(&self.pool, &path).and_then(|o| {
            if binary {
                run_binary(&path, &self.dir.join("out"), &o)?;
            }
            Ok(o)
        });
        (r, path)
    }
}

fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name).ok().map(|v| {
        v.trim()
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v}: not a whole number"))
    })
}

/// A mutated deck: the index of its seed, its text, the files beside it, what was done.
struct Case {
    seed: usize,
    text: Vec<u8>,
    beside: Vec<(String, Vec<u8>)>,
    log: Vec<String>,
}

/// Case `n`: its seed and mutated deck, and the log of the mutations.
fn make_case(seeds: &[Seed], n: u64) -> Case {
    let mut rng = Rng::for_case(n);
    let total: u32 = seeds.iter().map(|s| s.weight).sum();
    let mut w = rng.below(total as usize) as u32;
    let si = seeds
        .iter()
        .position(|s| {
            if w < s.weight {
                true
            } else {
                w -= s.weight;
                false
            }
        })
        .unwrap();
    let seed = &seeds[si];
    let mut lines: Vec<Vec<u8>> = seed
        .text
        .split(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect();
    let mut log = Vec::new();
    let k = 1 + (0..5).take_while(|_| rng.chance(0.45)).count();
    for _ in 0..k {
        log.push(mutate(&mut rng, &mut lines));
    }
    let mut beside = seed.beside.clone();
    if !beside.is_empty() && rng.chance(0.2) {
        // the included mesh cut short or a byte of it changed
        let b = &mut beside[0].1;
        if rng.chance(0.5) {
            let n = rng.below(b.len());
            b.truncate(n);
            log.push(format!("{} truncated at byte {n}", beside[0].0));
        } else {
            let n = rng.below(b.len());
            b[n] = *rng.pick(b"0123456789-.e \n$*abc");
            log.push(format!("{} byte {n} changed", beside[0].0));
        }
    }
    Case {
        seed: si,
        text: lines.join(&b'\n'),
        beside,
        log,
    }
}

/// Where a failing case's deck is kept.
fn keep(name: &str, text: &[u8], beside: &[(String, Vec<u8>)]) -> PathBuf {
    let dir = std::env::temp_dir().join("cleave-fuzz-failures");
    std::fs::create_dir_all(&dir).unwrap();
    for (n, b) in beside {
        std::fs::write(dir.join(n), b).unwrap();
    }
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The fuzz campaign: [`DEFAULT_CASES`] mutated decks (or `FUZZ_CASES`, or as many as fit
/// in `FUZZ_SECONDS`, from case `FUZZ_START`; `FUZZ_CASE=N` runs case N alone and shows
/// it). Fails listing every case that panicked, hung, or ran to non-finite figures, or where
/// the binary's exit code broke the interface's rules (module doc).
#[test]
fn fuzz_deck_mutations() {
    let bench = Bench::new("fuzz");
    let seeds = seeds(&bench.dir);
    let one = env_u64("FUZZ_CASE");
    let start = one.or(env_u64("FUZZ_START")).unwrap_or(0);
    let seconds = env_u64("FUZZ_SECONDS");
    let cases = if one.is_some() {
        1
    } else if seconds.is_some() {
        u64::MAX
    } else {
        env_u64("FUZZ_CASES").unwrap_or(DEFAULT_CASES)
    };
    let t0 = Instant::now();
    let mut failures = Vec::new();
    let mut counts = [0u64; 3];
    let mut ran = 0;
    let mut steps_run = 0;
    let log_all = std::env::var_os("FUZZ_LOG").is_some();
    let mut per_seed = vec![0u64; seeds.len()];
    for n in start..start.saturating_add(cases) {
        if seconds.is_some_and(|s| t0.elapsed().as_secs() >= s) {
            break;
        }
        let Case {
            seed: si,
            text,
            beside,
            log,
        } = make_case(&seeds, n);
        per_seed[si] += 1;
        let binary = one.is_some() || n % BINARY_EVERY == 0;
        let (r, _) = bench.case(&text, &beside, binary);
        ran += 1;
        if log_all {
            eprintln!("case {n} [{}] {}: {r:?}", seeds[si].name, log.join("; "));
        }
        if one.is_some() {
            let p = keep(&format!("case-{n}.k"), &text, &beside);
            eprintln!(
                "case {n}: seed {}; {}\n  deck: {}\n  outcome: {r:?}",
                seeds[si].name,
                log.join("; "),
                p.display()
            );
        }
        match r {
            Ok(Outcome::Input(_)) => counts[0] += 1,
            Ok(Outcome::Numerical(_)) => counts[1] += 1,
            Ok(Outcome::Ran { steps, .. }) => {
                counts[2] += 1;
                steps_run += steps;
            }
            Err(m) => {
                let p = keep(&format!("case-{n}.k"), &text, &beside);
                let line = format!(
                    "case {n} (seed {}; {}): {m}\n    deck kept in {}; rerun with FUZZ_CASE={n}",
                    seeds[si].name,
                    log.join("; "),
                    p.display()
                );
                eprintln!("FUZZ FAILURE {line}");
                let hang = m.starts_with("hang");
                failures.push(line);
                if hang || failures.len() >= 50 {
                    break;
                }
            }
        }
        if ran % 10_000 == 0 {
            eprintln!(
                "fuzz: {ran} cases in {:.0} s, {} failures",
                t0.elapsed().as_secs_f64(),
                failures.len()
            );
        }
    }
    eprintln!(
        "fuzz: cases {start}..{} ({ran}) in {:.1} s: {} bad input, {} numerical failures, {} ran ({steps_run} steps); {} defects; cases per seed {per_seed:?}",
        start + ran,
        t0.elapsed().as_secs_f64(),
        counts[0],
        counts[1],
        counts[2],
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {ran} fuzz cases failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    // the mutations must leave enough decks valid for the solver to be exercised
    if one.is_none() && ran >= 500 {
        assert!(
            counts[2] * 20 >= ran,
            "only {} of {ran} cases ran",
            counts[2]
        );
    }
}

/// The corpus (`tests/fuzz-corpus/*.k`): each deck runs in process and through the binary
/// with the campaign's checks, and a deck with a `$ expect: CODE TEXT` line must end with
/// that exit code and TEXT in its error message. The corpus keeps every defect the fuzzing
/// found fixed.
#[test]
fn fuzz_corpus_replays() {
    let bench = Bench::new("fuzz-corpus");
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "k"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{} corpus decks", files.len());
    let mut failures = Vec::new();
    for f in &files {
        let text = std::fs::read(f).unwrap();
        let head = String::from_utf8_lossy(&text);
        assert!(
            head.starts_with("$ "),
            "{}: the first line must say what the deck exercises",
            f.display()
        );
        let expect = head
            .lines()
            .find_map(|l| l.strip_prefix("$ expect: "))
            .map(|e| {
                let (code, what) = e.split_once(' ').unwrap_or((e, ""));
                (
                    code.parse::<i32>().expect("$ expect: CODE TEXT"),
                    what.trim().to_string(),
                )
            });
        let (r, path) = bench.case(&text, &[], true);
        let problem = match (&r, &expect) {
            (Err(m), _) => Some(m.clone()),
            (Ok(o), Some((code, what))) => {
                let p = path.to_str().unwrap();
                let (c, err) = cleave_limited(&[
                    "run",
                    p,
                    "-q",
                    "--threads",
                    "1",
                    "-o",
                    bench.dir.join("out").to_str().unwrap(),
                ])
                .unwrap_or((None, String::new()));
                (c != Some(*code) || !err.contains(what.as_str())).then(|| {
                    format!(
                        "expected exit {code} with '{what}', got {c:?}: {err} (in process: {o:?})"
                    )
                })
            }
            _ => None,
        };
        if let Some(m) = problem {
            failures.push(format!("{}: {m}", f.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every seed, unmutated, reads, builds and runs its steps: a seed that is already bad
/// input would leave the solver untested by its mutations.
#[test]
fn fuzz_seeds_run_unmutated() {
    let bench = Bench::new("fuzz-seeds");
    let seeds = seeds(&bench.dir);
    for s in &seeds {
        let (r, _) = bench.case(&s.text, &s.beside, true);
        assert!(matches!(r, Ok(Outcome::Ran { .. })), "{}: {r:?}", s.name);
    }
}

/// The generator is deterministic: a case number gives the same deck every time (what
/// makes `FUZZ_CASE=N` reproduce a failure), and different numbers give different decks.
#[test]
fn fuzz_cases_are_reproducible() {
    let dir = common::tmp("fuzz-repro");
    let seeds = seeds(&dir);
    let a: Vec<_> = (0..50).map(|n| make_case(&seeds, n).text).collect();
    let b: Vec<_> = (0..50).map(|n| make_case(&seeds, n).text).collect();
    assert_eq!(a, b);
    let distinct: std::collections::HashSet<_> = a.iter().collect();
    assert!(
        distinct.len() >= 45,
        "{} distinct decks of 50",
        distinct.len()
    );
}

/// The checks catch what they are for: a panic and a hang in the guarded run are failures,
/// not passes (a fuzz harness that cannot fail proves nothing), a missing deck is bad input,
/// and a non-finite figure in glstat.csv is caught.
#[test]
fn the_guard_reports_panics_and_hangs() {
    let pool = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap(),
    );
    let r = guarded(&pool, CASE_LIMIT, || panic!("boom"));
    assert_eq!(r.unwrap_err(), "panic: boom");
    let r = guarded(&pool, Duration::from_millis(50), || {
        std::thread::sleep(Duration::from_millis(500));
        Ok(Outcome::Ran { steps: 0, t: 0.0 })
    });
    assert!(r.as_ref().unwrap_err().starts_with("hang"), "{r:?}");
    let r = run_guarded(&pool, Path::new("/nonexistent/deck.k"));
    assert!(matches!(r, Ok(Outcome::Input(_))), "{r:?}");
    let d = common::tmp("fuzz-guard");
    std::fs::write(d.join("glstat.csv"), "time,dt\n0,1e-7\n1e-7,NaN\n").unwrap();
    std::fs::write(d.join("summary.json"), "{\"energy_ratio\": 1.0}").unwrap();
    let e = finite_output(&d).unwrap_err();
    assert!(e.contains("row 2"), "{e}");
    std::fs::write(d.join("glstat.csv"), "time,dt\n0,1e-7\n").unwrap();
    assert_eq!(finite_output(&d), Ok(()));
}
