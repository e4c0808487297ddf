//! The paper's section 4 through the command line, shortened (issue 5): the ceramic ball
//! through its first contact, and the notched beam through crack initiation and growth.
//! `cargo test --release -p cleave --test paper_studies -- --nocapture` prints the numbers.

mod common;

use common::{cleave, csv, tmp};

fn summary(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn column(h: &[String], name: &str) -> usize {
    h.iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

/// The 2800-element ball through its first 40 us (it touches the plate at 1.3 us; the contact
/// lasts about 10 us; the coarser balls only crack at the example's SLSFAC, see
/// `example::ball_impact::SLSFAC`): interfaces fail and it breaks (more than the ball and the plate at the
/// end); all its mass is in fragments.csv; its momentum normal to the plate has turned
/// upwards (the plate pushed it back) while nothing acted across the plate, along x
/// (|p_x| < 2% of |p_z|); the energy balance, with the contact energy (springs and friction),
/// closes within 1e-3; contact forces were recorded.
#[test]
fn ball_breaks_on_first_contact_with_momentum_and_energy_accounted() {
    let d = tmp("ball-short");
    let deck = d.join("ball.k");
    let deck = deck.to_str().unwrap();
    assert!(
        cleave(&["example", "ball-impact", "--elements", "2800", "-o", deck])
            .status
            .success()
    );
    let out = d.join("out");
    let r = cleave(&[
        "run",
        deck,
        "--end-time",
        "40e-6",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let s = summary(&out);
    let failed = s["failed_interfaces"].as_u64().unwrap();
    let fragments = s["fragments"].as_u64().unwrap();
    let ratio = s["energy_ratio"].as_f64().unwrap();
    let (h, rows) = csv(&out.join("fragments.csv"));
    let (mass, vx, vy, vz) = (
        column(&h, "mass"),
        column(&h, "vx"),
        column(&h, "vy"),
        column(&h, "vz"),
    );
    // the plate is the heaviest fragment (its 25 rigid bricks); the rest is the ball
    let ball: Vec<&Vec<f64>> = rows.iter().skip(1).collect();
    let m_ball: f64 = ball.iter().map(|r| r[mass]).sum();
    let p = |c: usize| ball.iter().map(|r| r[mass] * r[c]).sum::<f64>();
    let m_expected = 3960.0 * std::f64::consts::PI / 6.0 * 0.01f64.powi(3);
    let (hc, rc) = csv(&out.join("rcforc.csv"));
    let pairs = column(&hc, "pairs");
    let most_pairs = rc.iter().map(|r| r[pairs]).fold(0.0, f64::max);
    println!(
        "ball 2800, 40 us: {failed} failed interfaces, {fragments} fragments, ball mass {m_ball:.4e} kg (sphere {m_expected:.4e}), p = ({:.3e}, {:.3e}, {:.3e}) kg m/s (initially (0, {:.3e}, {:.3e})), energy ratio {ratio:.6}, up to {most_pairs} contact pairs",
        p(vx),
        p(vy),
        p(vz),
        -75.0 * m_ball,
        50.0 * m_ball
    );
    assert!(failed > 0);
    assert!(fragments > 2);
    // the O-grid sphere is a polyhedron inside the sphere: less volume (3% at 648 elements)
    assert!((m_ball / m_expected - 1.0).abs() < 0.1);
    assert!(p(vy) > 0.0, "the plate pushed the ball back up");
    assert!(p(vx).abs() < 0.02 * p(vz).abs());
    assert!((ratio - 1.0).abs() < 1e-3);
    assert!(most_pairs > 0.0);
}

/// The notched beam (MODEL 1) to 0.2 ms: the crack starts at the notch tip (the first failed
/// interfaces within 2 mm of the tip line, y = 25 mm, |x| < 3 mm) between 50 and 150 us (the
/// impactor touches at 1 us; the paper: 134 us), then runs up the centre-line (every failed
/// interface in the separation strip, |x| <= 2.8 mm plus the crack's opening, the crack tip
/// above y = 35 mm, a crack length over 10 mm at the end), and the energy balance holds within
/// 1e-3.
#[test]
fn beam_crack_starts_at_the_notch_and_runs_up_the_centre_line() {
    let d = tmp("beam-short");
    let deck = d.join("beam.k");
    let deck = deck.to_str().unwrap();
    assert!(cleave(&["example", "three-point-bend", "-o", deck])
        .status
        .success());
    let out = d.join("out");
    let r = cleave(&[
        "run",
        deck,
        "--end-time",
        "0.2e-3",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let s = summary(&out);
    let t0 = s["crack_initiation_time"]
        .as_f64()
        .expect("the crack starts");
    let (h, rows) = csv(&out.join("crack.csv"));
    let c = |n: &str| column(&h, n);
    let first = rows
        .iter()
        .find(|r| r[c("failed_interfaces")] > 0.0)
        .unwrap();
    let last = rows.last().unwrap();
    println!(
        "beam to 0.2 ms: initiation {:.1} us at x in [{:.2}, {:.2}] mm, y in [{:.2}, {:.2}] mm; at the end {} failed interfaces, x in [{:.2}, {:.2}] mm, y up to {:.2} mm, crack length {:.2} mm, energy ratio {:.6}",
        t0 * 1e6,
        first[c("min_x")] * 1e3,
        first[c("max_x")] * 1e3,
        first[c("min_y")] * 1e3,
        first[c("max_y")] * 1e3,
        last[c("failed_interfaces")],
        last[c("min_x")] * 1e3,
        last[c("max_x")] * 1e3,
        last[c("max_y")] * 1e3,
        last[c("crack_length")] * 1e3,
        s["energy_ratio"].as_f64().unwrap()
    );
    assert!(t0 > 50e-6 && t0 < 150e-6);
    assert!((first[c("min_y")] - 0.025).abs() < 2e-3 && (first[c("max_y")] - 0.025).abs() < 2e-3);
    assert!(first[c("min_x")] > -3e-3 && first[c("max_x")] < 3e-3);
    // the strip and its border faces reach |x| = 2.8 mm; current positions, opened by the crack
    assert!(last[c("min_x")] > -4e-3 && last[c("max_x")] < 4e-3);
    assert!(last[c("max_y")] > 0.035);
    assert!(last[c("crack_length")] > 0.01);
    assert!((s["energy_ratio"].as_f64().unwrap() - 1.0).abs() < 1e-3);
}
