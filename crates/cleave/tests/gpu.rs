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

use common::{cleave, csv, example_deck, no_gpu, tmp, BASE};

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
    if !same_outputs(&deck, &d, &["glstat.csv", "nodout.csv", "elout.csv"]) {
        return;
    }
    let summary = std::fs::read_to_string(d.join("gpu/summary.json")).unwrap();
    assert!(summary.contains("\"device\": \"gpu: "), "{summary}");
}

/// Two cubes, one pushed into the other at an angle, through surface to surface contact with
/// friction: `--gpu` writes the contact resultants (rcforc.csv) and the ledger with its contact
/// energy as the CPU does.
#[test]
fn gpu_run_with_contact_writes_what_the_cpu_run_writes() {
    let d = tmp("gpu-contact");
    let deck = write_deck(&d, CUBES);
    if !same_outputs(&deck, &d, &["glstat.csv", "rcforc.csv", "nodout.csv"]) {
        return;
    }
    let (h, rows) = csv(&d.join("gpu/rcforc.csv"));
    let fx = h.iter().position(|c| c == "fx").unwrap();
    assert!(rows.iter().any(|r| r[fx] != 0.0), "the cubes touched");
}

/// The fragmenting bar of `cleave example fragmenting-bar` (60 elements, every interface
/// cohesive with a random strength, single surface contact between the fragments): `--gpu`
/// breaks it into the same fragments as the CPU, the fragments that spring back closing on
/// their neighbours through the contact. Its failures follow each other within round-off of
/// their strengths, so the two runs part after the first failures (the GPU sums in other
/// orders): measured, 32 interfaces and 5 fragments on both, fragments.csv's element counts and
/// masses the same, the kinetic energy at the end within 0.4% and the total within 1e-4. The
/// test asks for the same fragments and the energies within 2% (the issue's "within a few per
/// cent").
#[test]
fn gpu_fragments_the_bar_as_the_cpu() {
    let d = tmp("gpu-fragmenting-bar");
    let deck = example_deck(&d, "bar.k", "fragmenting-bar", &["--elements", "60"]);
    let g = run(&deck, &d.join("gpu"), true);
    if no_gpu(&g) {
        return;
    }
    assert_eq!(
        g.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&g.stderr)
    );
    assert_eq!(run(&deck, &d.join("cpu"), false).status.code(), Some(0));
    let last = |dir: &str| {
        let (h, rows) = csv(&d.join(dir).join("glstat.csv"));
        let col = |name: &str| h.iter().position(|c| c == name).unwrap();
        let r = rows.last().unwrap().clone();
        let pick = |name: &str| r[col(name)];
        (
            [pick("failed_interfaces"), pick("fragments")],
            [
                pick("kinetic_energy"),
                pick("contact_energy"),
                pick("total_energy"),
            ],
        )
    };
    let (cpu, gpu) = (last("cpu"), last("gpu"));
    eprintln!("fragmenting bar: CPU {cpu:?}, GPU {gpu:?}");
    assert_eq!(cpu.0, gpu.0, "failed interfaces and fragments");
    assert!(cpu.0[1] >= 3.0, "it fragments: {:?}", cpu.0);
    for k in 0..3 {
        assert!(
            (cpu.1[k] - gpu.1[k]).abs() <= 0.02 * cpu.1[k].abs(),
            "energy {k}: {} vs {}",
            cpu.1[k],
            gpu.1[k]
        );
    }
    assert!(gpu.1[1] > 0.0, "the fragments meet through the contact");
    let frags = |dir: &str| {
        let (_, rows) = csv(&d.join(dir).join("fragments.csv"));
        rows.iter().map(|r| (r[1], r[2])).collect::<Vec<_>>()
    };
    assert_eq!(frags("cpu"), frags("gpu"), "fragments' elements and masses");
}

/// The paper's ball on its rigid plate (`cleave example ball-impact --elements 256`, to 20 us):
/// `--gpu` breaks it as the CPU does, the crack faces joining the contact with the rigid plate's
/// faces: glstat (131 failed interfaces, 3 fragments by 20 us) and rcforc within 1e-9 of the
/// CPU's (measured: 1e-14), and the same fragments. Its failures are far enough from their
/// strengths' round-off to come in the same steps on both.
#[test]
fn gpu_breaks_the_ball_on_its_plate_as_the_cpu() {
    let d = tmp("gpu-ball");
    let args = ["--elements", "256", "--end-time", "2e-5"];
    let deck = example_deck(&d, "ball.k", "ball-impact", &args);
    if !same_outputs(&deck, &d, &["glstat.csv", "rcforc.csv"]) {
        return;
    }
    let (h, rows) = csv(&d.join("gpu/glstat.csv"));
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let last = rows.last().unwrap();
    assert!(last[col("failed_interfaces")] >= 100.0, "it breaks");
    assert!(last[col("fragments")] >= 2.0, "into pieces");
    // the same fragments: elements, and masses to round-off
    let frags = |dir: &str| csv(&d.join(dir).join("fragments.csv")).1;
    let (a, b) = (frags("cpu"), frags("gpu"));
    assert_eq!(a.len(), b.len(), "fragments");
    for (ra, rb) in a.iter().zip(&b) {
        assert_eq!(ra[1], rb[1], "elements of fragment {}", ra[0]);
        assert!(
            (ra[2] - rb[2]).abs() <= 1e-12 * ra[2],
            "mass of fragment {}",
            ra[0]
        );
    }
}

/// Two one-element steel cubes 10 mm a side (parts 1 and 2), the second 10 um beyond the first
/// along x and offset by a fraction of a side in y and z, the first at 10 m/s along x and 3 m/s
/// along y.
const CUBES: &str = "*KEYWORD
*CONTROL_TERMINATION
2.0e-5
*DATABASE_GLSTAT
1.0e-6
*DATABASE_RCFORC
1.0e-6
*DATABASE_HISTORY_NODE
9
*MAT_ELASTIC
1,7800.0,2.0e11,0.3
*SECTION_SOLID
1,1
*PART
left
1,1,1
*PART
right
2,1,1
*NODE
1,0.0,0.0,0.0
2,0.01,0.0,0.0
3,0.01,0.01,0.0
4,0.0,0.01,0.0
5,0.0,0.0,0.01
6,0.01,0.0,0.01
7,0.01,0.01,0.01
8,0.0,0.01,0.01
9,0.01001,0.003,0.002
10,0.02001,0.003,0.002
11,0.02001,0.013,0.002
12,0.01001,0.013,0.002
13,0.01001,0.003,0.012
14,0.02001,0.003,0.012
15,0.02001,0.013,0.012
16,0.01001,0.013,0.012
*ELEMENT_SOLID
1,1,1,2,3,4,5,6,7,8
2,2,9,10,11,12,13,14,15,16
*INITIAL_VELOCITY_NODE
1,10.0,3.0,0.0
2,10.0,3.0,0.0
3,10.0,3.0,0.0
4,10.0,3.0,0.0
5,10.0,3.0,0.0
6,10.0,3.0,0.0
7,10.0,3.0,0.0
8,10.0,3.0,0.0
*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE
1,2,3,3
0.3,0.2,0.0
*END
";

/// Run `deck` on the CPU and the GPU (into `dir`'s cpu and gpu) and compare `files`: the same
/// columns and rows, every value within 1e-9 of its column's largest; false without a GPU.
fn same_outputs(deck: &Path, d: &Path, files: &[&str]) -> bool {
    let (c, g) = (d.join("cpu"), d.join("gpu"));
    let out = run(deck, &g, true);
    if no_gpu(&out) {
        return false;
    }
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(run(deck, &c, false).status.code(), Some(0));
    for f in files {
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
    true
}

#[test]
fn gpu_refuses_what_it_lacks_by_name() {
    let d = tmp("gpu-refuses");
    let text = BASE.replace(
        "*END",
        "*SET_NODE_LIST\n9\n2, 5, 8, 11\n*CONSTRAINED_NODAL_RIGID_BODY\n50, , 9\n*MAT_ADD_SEPARATION\n1, 1, 1.0e30\n*END",
    );
    let deck = write_deck(&d, &text);
    // the CPU runs the deck; the GPU names what it lacks (a nodal rigid body on nodes of the
    // separation group: the CPU keeps each copy apart there), whether or not a GPU is present
    assert_eq!(run(&deck, &d.join("cpu"), false).status.code(), Some(0));
    let out = run(&deck, &d.join("gpu"), true);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains(
            "--gpu does not run a rigid body bonded to the nodes of a separation group (node 2)"
        ),
        "{err}"
    );
    assert!(!d.join("gpu").exists(), "no output is started");
}

/// The benchmarks that time the CPU alone are refused with `--gpu` (exit 2, nothing run), never
/// run on the CPU instead; so is `--passes` anywhere but on `bench ball --gpu`.
#[test]
fn gpu_benchmarks_that_need_what_it_lacks_are_refused() {
    let passes = "--passes times each pass of the GPU's step over a run: it goes with `cleave bench ball --gpu`";
    let cases: [(&[&str], &str); 4] = [
        (
            &["bench", "paper-tables", "--gpu"],
            "`cleave bench paper-tables` runs on the CPU only",
        ),
        (
            &["bench", "fragmentation", "--gpu"],
            "`cleave bench fragmentation` runs on the CPU only",
        ),
        (&["bench", "ball", "--passes"], passes),
        (&["bench", "cube", "--gpu", "--passes"], passes),
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
