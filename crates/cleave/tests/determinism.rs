//! The same deck gives the same numbers on every run and every thread count: the ball (with
//! separation, fragments and contact) and the notched beam (plasticity, rigid bodies driven
//! by prescribed motion, contact) run with 1, 2 and 3 threads must write byte-identical
//! histories and crack files.

mod common;

use common::{cleave, tmp};

/// Run `deck` to `end` with each thread count; every listed output file must be identical.
/// Returns the scratch folder (removed when dropped) and the first run's output folder.
fn same_on_every_thread_count(
    name: &str,
    example: &[&str],
    end: &str,
    files: &[&str],
) -> (common::Scratch, std::path::PathBuf) {
    let d = tmp(name);
    let deck = d.join("deck.k");
    let deck = deck.to_str().unwrap();
    let mut args = vec!["example"];
    args.extend_from_slice(example);
    args.extend_from_slice(&["-o", deck]);
    assert!(cleave(&args).status.success());
    let outs: Vec<_> = ["1", "2", "3"]
        .iter()
        .map(|t| {
            let out = d.join(format!("t{t}"));
            let r = cleave(&[
                "run",
                deck,
                "--end-time",
                end,
                "--threads",
                t,
                "-q",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
            out
        })
        .collect();
    for f in files {
        let first = std::fs::read(outs[0].join(f)).unwrap();
        assert!(!first.is_empty(), "{f} is empty");
        for o in &outs[1..] {
            assert!(
                std::fs::read(o.join(f)).unwrap() == first,
                "{name}: {f} differs between 1 thread and {}",
                o.display()
            );
        }
    }
    println!(
        "{name}: {} identical on 1, 2 and 3 threads",
        files.join(", ")
    );
    let first = outs.into_iter().next().unwrap();
    (d, first)
}

#[test]
fn fragmenting_ball_is_bit_identical_on_1_2_3_threads() {
    let _ = same_on_every_thread_count(
        "det-ball",
        &["ball-impact", "--elements", "256"],
        "20e-6",
        &[
            "glstat.csv",
            "rcforc.csv",
            "nodout.csv",
            "elout.csv",
            "crack.csv",
            "fragments.csv",
        ],
    );
}

#[test]
fn notched_beam_is_bit_identical_on_1_2_3_threads() {
    let _ = same_on_every_thread_count(
        "det-beam",
        &["three-point-bend"],
        "20e-6",
        &["glstat.csv", "rcforc.csv", "nodout.csv", "elout.csv"],
    );
}

/// Weibull interface strengths (`--weibull 6 --seed 3`): drawn per interface from the seed and
/// the element pair, so the strengths, the cracks and the fragments are the same on every
/// thread count; the run writes the strength histogram and each crack face's strength.
#[test]
fn ball_with_weibull_strengths_is_bit_identical_on_1_2_3_threads() {
    let (_scratch, out) = same_on_every_thread_count(
        "det-weibull",
        &[
            "ball-impact",
            "--elements",
            "256",
            "--weibull",
            "6",
            "--seed",
            "3",
        ],
        "20e-6",
        &["glstat.csv", "crack.csv", "fragments.csv"],
    );
    assert!(out.join("strength.png").is_file());
    let last = std::fs::read_dir(out.join("cracks"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .max()
        .unwrap();
    let vtp = std::fs::read(last).unwrap();
    let text = String::from_utf8_lossy(&vtp);
    assert!(
        text.contains("Name=\"strength\""),
        "crack faces carry their strength"
    );
}

/// The Taylor bar on ELFORM 13 tetrahedra: the nodal averaging of the volume change and the
/// pressure (gathers in a fixed order) gives the same bits on every thread count.
#[test]
fn nodal_pressure_tetrahedra_are_bit_identical_on_1_2_3_threads() {
    let _ = same_on_every_thread_count(
        "det-tet13",
        &["taylor-bar", "--shape", "tet13"],
        "5e-6",
        &["glstat.csv", "nodout.csv", "elout.csv"],
    );
}

/// The Taylor bar on ELFORM 2: the Gauss points' pass runs before the coloured scatter, so
/// the same bits on every thread count.
#[test]
fn selectively_reduced_hexahedra_are_bit_identical_on_1_2_3_threads() {
    let _ = same_on_every_thread_count(
        "det-hex2",
        &["taylor-bar", "--shape", "hex2"],
        "5e-6",
        &["glstat.csv", "nodout.csv", "elout.csv"],
    );
}
