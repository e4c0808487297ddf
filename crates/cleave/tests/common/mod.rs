//! Helpers shared by the end-to-end tests: run the binary, a fresh scratch folder, read a CSV.

#![allow(dead_code)] // each test file uses its own subset of the helpers

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `cleave` binary with `args`.
pub fn cleave(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cleave"))
        .args(args)
        .output()
        .expect("cleave runs")
}

/// `cleave example NAME ARGS -o DIR/FILE` (DIR made first): the deck's path; panics with
/// cleave's message when it fails.
pub fn example_deck(dir: &Path, file: &str, name: &str, args: &[&str]) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let deck = dir.join(file);
    let mut all = vec!["example", name];
    all.extend_from_slice(args);
    all.extend(["-o", deck.to_str().unwrap()]);
    let out = cleave(&all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    deck
}

/// A scratch folder for one test, removed when the test passes (the guard drops) and kept
/// when it fails (dropped while panicking), so a failure can be looked at and passing runs
/// leave nothing behind: the paper studies alone write some 165 MB a run.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept for inspection: {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// True (and says SKIPPED) when a `--gpu` run found no usable GPU (exit 1 with the device
/// message).
pub fn no_gpu(out: &Output) -> bool {
    let err = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(1) && err.contains("--gpu:") {
        eprintln!("SKIPPED: {err}");
        return true;
    }
    false
}

/// A fresh, empty scratch folder for one test (see [`Scratch`]).
pub fn tmp(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("cleave-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

/// Header and rows of a CSV file, numbers parsed (empty fields as NaN); every row has as many
/// fields as the header.
pub fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect::<Vec<_>>();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse::<f64>().unwrap_or(f64::NAN))
                .collect::<Vec<_>>()
        })
        .collect::<Vec<_>>();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{}", path.display());
    }
    (header, rows)
}

/// A valid 2x1x1 elastic bar deck, free format, pulled at x = 2 by a prescribed velocity.
/// Line numbers below refer to this text.
pub const BASE: &str = "*KEYWORD
*CONTROL_TERMINATION
1.0e-5
*DATABASE_GLSTAT
1.0e-6
*DATABASE_HISTORY_NODE
3
*DATABASE_HISTORY_SOLID
1
*MAT_ELASTIC
1,7800.0,2.0e11,0.3
*SECTION_SOLID
1,1
*PART
bar
1,1,1
*NODE
1,0.0,0.0,0.0
2,0.01,0.0,0.0
3,0.02,0.0,0.0
4,0.0,0.01,0.0
5,0.01,0.01,0.0
6,0.02,0.01,0.0
7,0.0,0.0,0.01
8,0.01,0.0,0.01
9,0.02,0.0,0.01
10,0.0,0.01,0.01
11,0.01,0.01,0.01
12,0.02,0.01,0.01
*ELEMENT_SOLID
1,1,1,2,5,4,7,8,11,10
2,1,2,3,6,5,8,9,12,11
*DEFINE_CURVE
7
0.0,1.0
1.0,1.0
*BOUNDARY_SPC_NODE
1,0,1,1,1
4,0,1,1,1
7,0,1,1,1
10,0,1,1,1
*BOUNDARY_PRESCRIBED_MOTION_NODE
3,1,0,7,1.0
6,1,0,7,1.0
9,1,0,7,1.0
12,1,0,7,1.0
*END
";
