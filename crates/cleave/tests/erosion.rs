//! Element erosion through the command line: `cleave example ball-impact --erosion` writes the
//! ball with `*MAT_ADD_EROSION` at the separation strength; `cleave run` books what erodes in
//! glstat (two more columns), summary.json and the ParaView states; `--gpu` writes the same
//! ledger.

mod common;

use common::{cleave, csv, example_deck, tmp};

#[test]
fn an_eroding_ball_books_its_erosion_in_every_output() {
    let d = tmp("erosion-cli");
    let deck = example_deck(
        &d,
        "ball.k",
        "ball-impact",
        &["--elements", "425", "--erosion"],
    );
    let deck_s = deck.to_str().unwrap();
    let out = d.join("out");
    let text = std::fs::read_to_string(&deck).unwrap();
    assert!(text.contains("*MAT_ADD_EROSION"), "{text}");
    assert!(!text.contains("*MAT_ADD_SEPARATION"));
    let r = cleave(&[
        "run",
        deck_s,
        "--end-time",
        "6e-5",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let (h, rows) = csv(&out.join("glstat.csv"));
    let col = |name: &str| h.iter().position(|c| c == name).expect(name);
    let (ne, ee, ie, hg) = (
        col("eroded_elements"),
        col("eroded_energy"),
        col("internal_energy"),
        col("hourglass_energy"),
    );
    let last = rows.last().unwrap();
    assert!(last[ne] > 100.0, "eroded elements {}", last[ne]);
    // eroded energy: positive, never decreasing, part of internal + hourglass
    for w in rows.windows(2) {
        assert!(w[1][ee] >= w[0][ee] && w[1][ne] >= w[0][ne]);
    }
    assert!(
        last[ee] > 0.0 && last[ee] <= last[ie] + last[hg],
        "{last:?}"
    );
    let ratio = last[col("energy_ratio")];
    assert!((ratio - 1.0).abs() < 0.01, "energy ratio {ratio}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["eroded_elements"].as_f64(), Some(last[ne]));
    let states: Vec<_> = std::fs::read_dir(out.join("states")).unwrap().collect();
    let vtu = states
        .iter()
        .map(|e| e.as_ref().unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "vtu"))
        .unwrap();
    let bytes = std::fs::read(vtu).unwrap();
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    assert!(head.contains("Name=\"eroded\""), "{head}");

    // the GPU runs it too (contact on surfaces that erosion changes: the host changes them in
    // the steps elements erode), and writes the CPU's ledger
    let g = cleave(&[
        "run",
        deck_s,
        "--end-time",
        "6e-5",
        "--gpu",
        "-q",
        "-o",
        d.join("gpu").to_str().unwrap(),
    ]);
    if common::no_gpu(&g) {
        return;
    }
    let err = String::from_utf8_lossy(&g.stderr);
    assert_eq!(g.status.code(), Some(0), "{err}");
    let (hg_, rows_g) = csv(&d.join("gpu/glstat.csv"));
    assert_eq!(h, hg_);
    assert_eq!(rows.len(), rows_g.len());
    for (k, name) in h.iter().enumerate() {
        let scale = rows.iter().fold(0.0f64, |m, r| m.max(r[k].abs()));
        for (a, b) in rows.iter().zip(&rows_g) {
            assert!(
                (a[k] - b[k]).abs() <= 1e-9 * scale,
                "{name} at t = {}: {} on the CPU, {} on the GPU",
                a[0],
                a[k],
                b[k]
            );
        }
    }
}
