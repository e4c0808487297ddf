//! End-to-end element separation through the `cleave` binary: a deck with
//! `*MAT_ADD_SEPARATION` runs, reports its crack (summary, glstat, crack.csv, fragments.csv,
//! cracks.pvd), and with a strength nothing reaches gives the same node histories as the same
//! deck run with `--no-separation`.

mod common;

use std::path::{Path, PathBuf};

use common::{cleave, csv, tmp};

use cleave_core::curve::Curve;
use cleave_core::mesh::box_model;
use cleave_core::model::{
    Material, MaterialKind, Model, MotionTarget, PrescribedMotion, SeparationDef, Vad,
};

const RHO: f64 = 7800.0;
const YOUNG: f64 = 200e9;
const L: f64 = 0.1;
const N: usize = 40;
const PULL: f64 = 10.0;

fn run_ok(args: &[&str]) {
    let out = cleave(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The bar of the core tests as a deck: 40 x 1 x 1 elements, Poisson 0, both ends pulled
/// outwards at 10 m/s, all in one separation group of strength `sigmax` (MODEL 1); history
/// nodes on the middle plane and at x = L/4.
fn bar_deck(dir: &Path, sigmax: f64) -> PathBuf {
    let c = (YOUNG / RHO).sqrt();
    let h = L / N as f64;
    let mat = Material {
        id: 1,
        density: RHO,
        young: YOUNG,
        poisson: 0.0,
        kind: MaterialKind::Elastic,
    };
    let mut m: Model = box_model([N, 1, 1], [L, h, h], mat, 0.9 * L / c);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 1.0],
        y: vec![1.0, 1.0],
    });
    for (x, sf) in [(0.0, -PULL), (L, PULL)] {
        for node in m.nodes_where(0, x, 1e-12) {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(0),
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    m.separations.push(SeparationDef {
        material: 0,
        model: 1,
        sigmax,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    m.output.history_nodes = [
        m.nodes_where(0, L / 2.0, 1e-12),
        m.nodes_where(0, L / 4.0, 1e-12),
    ]
    .concat();
    m.output.glstat_dt = m.control.end_time / 50.0;
    m.output.nodout_dt = m.control.end_time / 50.0;
    m.output.d3plot_dt = m.control.end_time / 4.0;
    let p = dir.join("bar.k");
    std::fs::write(&p, cleave_io::deck::write_deck(&m)).unwrap();
    p
}

fn json_number(text: &str, key: &str) -> f64 {
    let at = text
        .find(&format!("\"{key}\""))
        .unwrap_or_else(|| panic!("{key}"));
    let rest = &text[at + key.len() + 2..];
    let rest = rest.trim_start_matches([':', ' ']);
    let end = rest.find([',', '\n', '}']).unwrap();
    rest[..end].trim().parse().unwrap()
}

/// MODEL 1 bar with SIGMAX = 1.5 rho c v: the run reports one failed interface of the 39, two
/// fragments of equal mass moving apart, the crack at the middle plane in crack.csv, and the
/// crack surface (two quads) in the last cracks/*.vtp.
#[test]
fn separation_deck_reports_the_crack() {
    let d = tmp("crack");
    let rcv = RHO * (YOUNG / RHO).sqrt() * PULL;
    let deck = bar_deck(&d, 1.5 * rcv);
    run_ok(&["run", deck.to_str().unwrap(), "--quiet"]);
    let out = d.join("bar.out");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert_eq!(json_number(&summary, "interfaces"), 39.0);
    assert_eq!(json_number(&summary, "failed_interfaces"), 1.0);
    assert_eq!(json_number(&summary, "fragments"), 2.0);
    assert_eq!(json_number(&summary, "nodes"), 164.0);
    assert_eq!(json_number(&summary, "nodes_solved"), 320.0);

    let (h, rows) = csv(&out.join("fragments.csv"));
    assert_eq!(h[0], "fragment");
    assert_eq!(rows.len(), 2);
    assert!(
        (rows[0][2] - rows[1][2]).abs() < 1e-12 * rows[0][2],
        "equal halves"
    );
    assert!(rows[0][6] * rows[1][6] < 0.0, "moving apart");

    let (h, rows) = csv(&out.join("crack.csv"));
    assert_eq!(h.len(), 12);
    assert_eq!(&h[10..], ["crack_length", "crack_speed"]);
    let last = rows.last().unwrap();
    let area = (L / N as f64).powi(2);
    assert_eq!(last[1], 1.0);
    assert!((last[2] - area).abs() < 1e-12 * area);
    assert_eq!(last[3], 2.0);
    assert!((last[4] - L / 2.0).abs() < 1e-3 && (last[5] - L / 2.0).abs() < 1e-3);
    assert!(rows[0][4].is_nan(), "no extent before the crack");
    // one interface: the crack is its origin, of length 0
    assert_eq!(last[10], 0.0);

    let (h, rows) = csv(&out.join("glstat.csv"));
    assert_eq!(h[10], "failed_interfaces");
    assert_eq!(rows.last().unwrap()[10], 1.0);
    assert_eq!(rows.last().unwrap()[11], 2.0);

    let pvd = std::fs::read_to_string(out.join("cracks.pvd")).unwrap();
    let last_vtp = pvd
        .lines()
        .filter_map(|l| l.split("file=\"").nth(1))
        .map(|r| r.split('"').next().unwrap().to_string())
        .next_back()
        .unwrap();
    let vtp = String::from_utf8_lossy(&std::fs::read(out.join(last_vtp)).unwrap()).to_string();
    assert!(vtp.contains("NumberOfPolys=\"2\""), "two crack faces");
    for f in ["crack.png", "crack_area.png", "fragments.png", "energy.png"] {
        assert!(out.join(f).exists(), "{f}");
    }
}

/// Continuity through the command line: with a strength nothing reaches, the split run's
/// node histories (each deck node the mass-weighted mean of its copies) equal those of
/// `--no-separation` to 1e-9 of the largest displacement.
#[test]
fn split_run_matches_the_unsplit_run_until_failure() {
    let d = tmp("continuity");
    let deck = bar_deck(&d, 1e30);
    let a = d.join("split");
    let b = d.join("plain");
    run_ok(&[
        "run",
        deck.to_str().unwrap(),
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    run_ok(&[
        "run",
        deck.to_str().unwrap(),
        "--quiet",
        "--no-separation",
        "-o",
        b.to_str().unwrap(),
    ]);
    let (_, ra) = csv(&a.join("nodout.csv"));
    let (_, rb) = csv(&b.join("nodout.csv"));
    assert_eq!(ra.len(), rb.len());
    let scale = rb.iter().map(|r| r[2].abs()).fold(0.0, f64::max);
    let worst = ra
        .iter()
        .zip(&rb)
        .flat_map(|(x, y)| (2..8).map(move |k| (x[k] - y[k]).abs()))
        .fold(0.0, f64::max);
    eprintln!(
        "continuity through the CLI: worst difference {worst:.2e}, displacement scale {scale:.2e}"
    );
    assert!(scale > 1e-6);
    assert!(worst < 1e-9 * scale.max(PULL * 1e-6));
    let summary = std::fs::read_to_string(a.join("summary.json")).unwrap();
    assert_eq!(json_number(&summary, "failed_interfaces"), 0.0);
}

/// The crack on the GPU (`--gpu`, where a device is found): the same failed interfaces and
/// fragments as the CPU run, and its glstat, nodout, crack.csv and fragments.csv to 1e-9 of
/// each column's largest value (at least 1e-6 of the file's) (round-off: see crates/cleave-gpu/tests/separation.rs).
#[test]
fn gpu_run_reports_the_crack_the_cpu_reports() {
    let d = tmp("crack-gpu");
    let rcv = RHO * (YOUNG / RHO).sqrt() * PULL;
    let deck = bar_deck(&d, 1.5 * rcv);
    let (c, g) = (d.join("cpu"), d.join("gpu"));
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let out = cleave(&["run", &path(&deck), "-q", "--gpu", "-o", &path(&g)]);
    if common::no_gpu(&out) {
        return;
    }
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    run_ok(&["run", &path(&deck), "-q", "-o", &path(&c)]);
    let sc = std::fs::read_to_string(c.join("summary.json")).unwrap();
    let sg = std::fs::read_to_string(g.join("summary.json")).unwrap();
    for key in ["failed_interfaces", "fragments", "nodes_solved"] {
        assert_eq!(json_number(&sc, key), json_number(&sg, key), "{key}");
    }
    assert_eq!(json_number(&sg, "failed_interfaces"), 1.0);
    for f in ["glstat.csv", "nodout.csv", "crack.csv", "fragments.csv"] {
        let (ha, ra) = csv(&c.join(f));
        let (hb, rb) = csv(&g.join(f));
        assert_eq!(ha, hb, "{f}");
        assert_eq!(ra.len(), rb.len(), "{f}: rows");
        // a column of round-off (a sideways velocity) on the scale of the file's largest value
        let finite = |r: &Vec<f64>, k: usize| r[k].is_finite().then_some(r[k].abs());
        let file_scale = (ra.iter())
            .flat_map(|r| (0..r.len()).filter_map(move |k| finite(r, k)))
            .fold(0.0f64, f64::max);
        for col in 0..ha.len() {
            let scale = (ra.iter())
                .filter_map(|r| finite(r, col))
                .fold(0.0f64, f64::max)
                .max(1e-6 * file_scale);
            for (a, b) in ra.iter().zip(&rb) {
                let same =
                    (a[col].is_nan() && b[col].is_nan()) || (a[col] - b[col]).abs() <= 1e-9 * scale;
                assert!(same, "{f} {}: {} vs {}", ha[col], a[col], b[col]);
            }
        }
    }
}
