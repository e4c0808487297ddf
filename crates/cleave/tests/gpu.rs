//! `cleave run --gpu`: the same output files as the CPU run (numbers to round-off), the same
//! numerical failure named, and a clear refusal of what the GPU step lacks.
//!
//! Needs a device with f64 shaders (on a machine without a GPU, Mesa's software Vulkan,
//! which `.ci/run` installs); without one, the tests that run on it say SKIPPED and pass.
//! Tolerance of the comparisons: see crates/cleave-gpu/tests/against_cpu.rs (round-off; here
//! 1e-9 of each column's largest value).

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{cleave, csv, no_gpu, tmp, BASE};

fn write_deck(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("deck.k");
    std::fs::write(&p, text).unwrap();
    p
}

fn run(deck: &Path, out: &Path, gpu: bool) -> Output {
    let mut args = vec![
        "run",
        deck.to_str().unwrap(),
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    if gpu {
        args.push("--gpu");
    }
    cleave(&args)
}

#[test]
fn gpu_run_writes_what_the_cpu_run_writes() {
    let d = tmp("gpu-outputs");
    let deck = write_deck(&d, BASE);
    let (c, g) = (d.join("cpu"), d.join("gpu"));
    let out = run(&deck, &g, true);
    if no_gpu(&out) {
        return;
    }
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(run(&deck, &c, false).status.code(), Some(0));
    for f in ["glstat.csv", "nodout.csv", "elout.csv"] {
        let (ha, ra) = csv(&c.join(f));
        let (hb, rb) = csv(&g.join(f));
        assert_eq!(ha, hb, "{f}");
        assert_eq!(ra.len(), rb.len(), "{f}: rows");
        assert!(ra.len() >= 5, "{f}: rows");
        // a column of round-off (a shear stress of a uniaxial bar) is compared on the scale of
        // the file's largest value
        let file_scale = ra.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..ha.len() {
            let scale = (ra.iter())
                .fold(0.0f64, |m, r| m.max(r[col].abs()))
                .max(1e-6 * file_scale);
            for (a, b) in ra.iter().zip(&rb) {
                assert!(
                    (a[col] - b[col]).abs() <= 1e-9 * scale,
                    "{f} {}: {} vs {}",
                    ha[col],
                    a[col],
                    b[col]
                );
            }
        }
    }
    let states = std::fs::read_dir(g.join("states")).unwrap().count();
    assert_eq!(states, std::fs::read_dir(c.join("states")).unwrap().count());
    let summary = std::fs::read_to_string(g.join("summary.json")).unwrap();
    assert!(summary.contains("\"device\": \"gpu: "), "{summary}");
}

#[test]
fn gpu_refuses_what_it_lacks_by_name() {
    let d = tmp("gpu-refuses");
    let text = BASE.replace("*END", "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n0,0,0\n*END");
    let deck = write_deck(&d, &text);
    // the CPU runs the deck; the GPU names the contact, whether or not a GPU is present
    assert_eq!(run(&deck, &d.join("cpu"), false).status.code(), Some(0));
    let out = run(&deck, &d.join("gpu"), true);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--gpu does not run contact (*CONTACT_...)"),
        "{err}"
    );
    assert!(!d.join("gpu").exists(), "no output is started");
}

/// The benchmarks that need contact are refused with `--gpu` by the feature the GPU lacks
/// (exit 2, nothing run), never run on the CPU instead.
#[test]
fn gpu_benchmarks_that_need_what_it_lacks_are_refused() {
    let cases: [(&[&str], &str); 4] = [
        (
            &["bench", "ball", "--gpu", "--elements", "256"],
            "--gpu does not run contact (*CONTACT_...)",
        ),
        (
            &[
                "bench",
                "ball",
                "--gpu",
                "--elements",
                "256",
                "--no-separation",
            ],
            "--gpu does not run contact (*CONTACT_...)",
        ),
        (
            &["bench", "paper-tables", "--gpu"],
            "`cleave bench paper-tables` runs contact",
        ),
        (
            &["bench", "fragmentation", "--gpu"],
            "`cleave bench fragmentation` runs contact",
        ),
    ];
    for (args, says) in cases {
        let out = cleave(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing measured");
    }
}

#[test]
fn gpu_numerical_failure_names_what_the_cpu_names() {
    let d = tmp("gpu-unstable");
    let text = BASE.replace("0.0,1.0\n1.0,1.0", "0.0,-1.0e4\n1.0,-1.0e4");
    let deck = write_deck(&d, &text);
    let g = run(&deck, &d.join("gpu"), true);
    if no_gpu(&g) {
        return;
    }
    let c = run(&deck, &d.join("cpu"), false);
    assert_eq!(c.status.code(), Some(3));
    assert_eq!(
        g.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&g.stderr)
    );
    // the same failure, element, time and step; only the output folder differs (Mesa's
    // software Vulkan adds a line of its own about XDG_RUNTIME_DIR where that is unset)
    let msg = |o: &Output, dir: &str| {
        String::from_utf8_lossy(&o.stderr)
            .replace(dir, "OUT")
            .lines()
            .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let cpu_dir = d.join("cpu");
    let gpu_dir = d.join("gpu");
    assert_eq!(
        msg(&c, cpu_dir.to_str().unwrap()),
        msg(&g, gpu_dir.to_str().unwrap())
    );
    // and the summary's step and time are the failure's on both
    let summary = |dir: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
    };
    let (sc, sg) = (summary(&cpu_dir), summary(&gpu_dir));
    assert!(sc["steps"].as_u64().is_some_and(|n| n > 0), "{sc}");
    assert_eq!(sc["steps"], sg["steps"], "{sc} vs {sg}");
}
