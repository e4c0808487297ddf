//! Runs that must end, and end clearly: a tiny output interval neither hangs nor floods the
//! disk, a collapsing time step stops at the DTMIN floor with exit 3 naming the element.

mod common;

use common::{cleave, tmp};

/// The bundled Taylor bar deck with `old` replaced by `new` in `dir/deck.k`.
fn taylor_with(dir: &std::path::Path, old: &str, new: &str) -> String {
    let text = std::fs::read_to_string(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/taylor-bar.k"),
    )
    .unwrap();
    assert!(text.contains(old), "{old}");
    let k = dir.join("deck.k");
    std::fs::write(&k, text.replacen(old, new, 1)).unwrap();
    k.to_str().unwrap().to_string()
}

/// `*DATABASE_GLSTAT` with DT 1e-30 writes a row every step and ends (it once counted the
/// multiples of DT one by one, for ever); `*DATABASE_BINARY_D3PLOT` with DT 1e-30 is refused
/// before the run (exit 2), as it would write a file of the whole mesh every step.
#[test]
fn a_tiny_output_interval_neither_hangs_nor_floods() {
    let d = tmp("tiny-dt");
    let k = taylor_with(
        &d,
        "*DATABASE_GLSTAT\n$#      dt\n      5e-7",
        "*DATABASE_GLSTAT\n$#      dt\n     1e-30",
    );
    let out = cleave(&["run", &k, "-q", "--end-time", "2e-6"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, rows) = common::csv(&d.join("deck.out/glstat.csv"));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("deck.out/summary.json")).unwrap())
            .unwrap();
    let steps = summary["steps"].as_u64().unwrap() as usize;
    assert!(
        rows.len() >= steps && rows.len() <= steps + 1,
        "{} rows, {steps} steps",
        rows.len()
    );
    let k = taylor_with(
        &d,
        "*DATABASE_BINARY_D3PLOT\n$#      dt\n      4e-6",
        "*DATABASE_BINARY_D3PLOT\n$#      dt\n     1e-30",
    );
    let out = cleave(&["run", &k, "-q"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("*DATABASE_BINARY_D3PLOT") && err.contains("at most 10000"),
        "{err}"
    );
}

/// DTMIN 0.8 on the Taylor bar: the foot's elements flatten against the wall and the step
/// falls below 0.8 of the first within the run, which stops with exit 3 naming the element,
/// the floor and the time; the histories written so far stay readable.
#[test]
fn a_collapsing_step_stops_at_the_dtmin_floor() {
    let d = tmp("dtmin");
    let k = taylor_with(
        &d,
        "*CONTROL_TERMINATION\n$#  endtim\n      8e-5",
        "*CONTROL_TERMINATION\n$#  endtim    endcyc     dtmin\n      8e-5                 0.8",
    );
    let out = cleave(&["run", &k, "-q"]);
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("fell below the floor") && err.contains("controlled by element"),
        "{err}"
    );
    let (_, rows) = common::csv(&d.join("deck.out/glstat.csv"));
    assert!(!rows.is_empty());
}
