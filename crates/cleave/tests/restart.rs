//! Restart files and output that survives a stop.
//!
//! - A run that writes restart files (`--checkpoint-every`) and is continued from the last one
//!   (`--restart`) gives the same bytes in every output file as a run never stopped: plastic
//!   Taylor bar with a rigid wall, ball impact with separation and contact, the ball eroding instead, the fragmenting bar
//!   (cohesive, random strengths), ELFORM 13 tetrahedra and ELFORM 2 hexahedra; continued on
//!   one thread after running on all.
//! - SIGTERM stops a run between two steps with a restart file, exit 143 and a summary that
//!   says "interrupted"; the continued run gives the same bytes.
//! - A run killed (SIGKILL) leaves files that are all valid (complete CSV rows, a .pvd that
//!   lists only complete states, a parseable summary.json), and continues from its last
//!   restart file to the same bytes.
//! - A restart file of another deck, of another version, or damaged is refused (exit 2).
//! - A GPU run (`--gpu`) continued from its restart file, written on schedule or at SIGTERM,
//!   gives the same bytes as a GPU run never stopped; a CPU run's file and a GPU run's are
//!   each refused by the other kind of run.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use common::{cleave, tmp};

/// Write the bundled example `name` (with `opts`) to `dir/deck.k`.
fn example(dir: &Path, name: &str, opts: &[&str]) -> String {
    let k = dir.join("deck.k");
    let ks = k.to_str().unwrap().to_string();
    let mut args = vec!["example", name, "-o", &ks];
    args.extend_from_slice(opts);
    let out = cleave(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    ks
}

fn run_ok(args: &[&str]) {
    let out = cleave(args);
    assert!(
        out.status.success(),
        "cleave {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every file under `dir`, relative, sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.push(p.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

/// The two output folders hold the same files with the same bytes, but for the restart file
/// and, in summary.json, the wall time, the time per element step and the memory.
fn assert_same_output(a: &Path, b: &Path) {
    let skip = |p: &PathBuf| p.as_os_str() == "restart.ckpt";
    let fa: Vec<_> = files(a).into_iter().filter(|p| !skip(p)).collect();
    let fb: Vec<_> = files(b).into_iter().filter(|p| !skip(p)).collect();
    assert_eq!(fa, fb, "{} and {}", a.display(), b.display());
    for f in &fa {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        if f.as_os_str() == "summary.json" {
            let mut x: serde_json::Value = serde_json::from_slice(&x).unwrap();
            let mut y: serde_json::Value = serde_json::from_slice(&y).unwrap();
            for k in ["wall_seconds", "us_per_element_step", "peak_rss_mb"] {
                x[k] = serde_json::Value::Null;
                y[k] = serde_json::Value::Null;
            }
            assert_eq!(x, y, "summary.json");
        } else {
            assert!(
                x == y,
                "{} differs ({} and {} bytes)",
                f.display(),
                x.len(),
                y.len()
            );
        }
    }
}

/// Run `deck` once through, and once with restart files every `every` continued from the
/// last one; the outputs must be the same bytes.
fn check_continuation(dir: &Path, deck: &str, every: &str, extra: &[&str]) {
    let full = dir.join("full");
    let part = dir.join("part");
    let (fs, ps) = (full.to_str().unwrap(), part.to_str().unwrap());
    fn with<'a>(v: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [v, extra].concat()
    }
    run_ok(&with(&["run", deck, "-q", "-o", fs], extra));
    run_ok(&with(
        &["run", deck, "-q", "-o", ps, "--checkpoint-every", every],
        extra,
    ));
    let ckpt = part.join("restart.ckpt");
    assert!(ckpt.exists(), "no restart file for {deck}");
    let cs = ckpt.to_str().unwrap();
    run_ok(&with(
        &["run", deck, "-q", "-o", ps, "--restart", cs],
        extra,
    ));
    assert_same_output(&full, &part);
}

#[test]
fn a_continued_run_writes_the_same_bytes() {
    let cases: [(&str, &[&str], &str, &[&str]); 6] = [
        ("taylor-bar", &[], "1.1e-5", &["--end-time", "2e-5"]),
        (
            "ball-impact",
            &["--elements", "425"],
            "1.6e-4",
            &["--end-time", "3e-4"],
        ),
        ("fragmenting-bar", &["--elements", "400"], "6e-7", &[]),
        (
            "taylor-bar",
            &["--shape", "tet13"],
            "2.6e-6",
            &["--end-time", "5e-6"],
        ),
        (
            "taylor-bar",
            &["--shape", "hex2"],
            "2.6e-6",
            &["--end-time", "5e-6"],
        ),
        // elements erode before and after the restart file (157 of 400 by 40 us, 311 by 60)
        (
            "ball-impact",
            &["--elements", "425", "--erosion"],
            "4e-5",
            &["--end-time", "6e-5"],
        ),
    ];
    for (k, (name, opts, every, extra)) in cases.iter().enumerate() {
        let d = tmp(&format!("restart-{k}"));
        let deck = example(&d, name, opts);
        check_continuation(&d, &deck, every, extra);
    }
}

/// Wait until `path` exists (and the child still runs), at most a minute.
fn wait_for(child: &mut Child, path: &Path) {
    let t0 = Instant::now();
    while !path.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before {} appeared",
            path.display()
        );
        assert!(t0.elapsed() < Duration::from_secs(60), "{}", path.display());
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_cleave"))
        .args(args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// Once the run writing into `out` has written its third state (its loop runs), SIGTERM it;
/// it must stop with exit 143. Its standard error.
#[cfg(unix)]
fn terminate(mut child: Child, out: &Path) -> String {
    wait_for(&mut child, &out.join("states/state_00002.vtu"));
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let res = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&res.stderr).into_owned();
    assert_eq!(res.status.code(), Some(143), "{err}");
    err
}

/// Continue `deck` into `out` from the restart file `ckpt`.
fn continue_from(deck: &str, out: &Path, ckpt: &Path) {
    let (o, c) = (out.to_str().unwrap(), ckpt.to_str().unwrap());
    run_ok(&["run", deck, "-q", "-o", o, "--restart", c]);
}

/// The Taylor bar over its 80 us: long enough (several seconds) to be stopped midway.
fn long_run(dir: &Path) -> (String, PathBuf) {
    let deck = example(dir, "taylor-bar", &[]);
    let full = dir.join("full");
    run_ok(&["run", &deck, "-q", "-o", full.to_str().unwrap()]);
    (deck, full)
}

#[cfg(unix)]
#[test]
fn sigterm_stops_with_a_restart_file_and_the_run_continues() {
    let d = tmp("restart-sigterm");
    let (deck, full) = long_run(&d);
    let out = d.join("out");
    let os = out.to_str().unwrap();
    let child = spawn(&["run", &deck, "-q", "-o", os]);
    let err = terminate(child, &out);
    assert!(
        err.contains("SIGTERM") && err.contains("--restart"),
        "{err}"
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "interrupted");
    let t = s["end_time"].as_f64().unwrap();
    assert!(t > 0.0 && t < 8e-5, "stopped at {t}");
    let ckpt = out.join("restart.ckpt");
    continue_from(&deck, &out, &ckpt);
    assert_same_output(&full, &out);
}

/// Every file a killed run leaves is valid: CSV rows complete and numeric, each state the
/// .pvd lists complete, summary.json parseable.
fn assert_valid_files(out: &Path) {
    for f in files(out) {
        let p = out.join(&f);
        match p.extension().and_then(|e| e.to_str()) {
            Some("csv") => {
                let (_, rows) = common::csv(&p);
                let text = std::fs::read_to_string(&p).unwrap();
                assert!(text.ends_with('\n'), "{}: a partial last row", f.display());
                if f.as_os_str() == "glstat.csv" {
                    assert!(!rows.is_empty());
                    assert!(
                        rows.iter().flatten().all(|x| x.is_finite()),
                        "{}",
                        f.display()
                    );
                }
            }
            Some("pvd") => {
                let text = std::fs::read_to_string(&p).unwrap();
                assert!(text.trim_end().ends_with("</VTKFile>"), "{}", f.display());
                for part in text.split("file=\"").skip(1) {
                    let name = &part[..part.find('"').unwrap()];
                    let state = std::fs::read(out.join(name)).unwrap();
                    assert!(state.ends_with(b"</VTKFile>\n"), "{name} is not complete");
                }
            }
            Some("json") => {
                let s: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
                assert_eq!(s["status"], "running");
            }
            _ => {}
        }
    }
}

#[cfg(unix)]
#[test]
fn a_killed_run_leaves_valid_files_and_continues_from_its_restart_file() {
    let d = tmp("restart-kill");
    let (deck, full) = long_run(&d);
    let out = d.join("out");
    let os = out.to_str().unwrap();
    let mut child = spawn(&["run", &deck, "-q", "-o", os, "--checkpoint-every", "1e-5"]);
    let ckpt = out.join("restart.ckpt");
    wait_for(&mut child, &ckpt);
    // past the restart file: the histories hold rows the continued run cuts off
    wait_for(&mut child, &out.join("states/state_00004.vtu"));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(out.join("summary.json").exists());
    assert_valid_files(&out);
    continue_from(&deck, &out, &ckpt);
    assert_same_output(&full, &out);
}

#[test]
fn a_restart_file_of_another_deck_version_or_damaged_is_refused() {
    let d = tmp("restart-refused");
    let deck = example(&d, "taylor-bar", &[]);
    let out = d.join("out");
    let os = out.to_str().unwrap();
    run_ok(&[
        "run",
        &deck,
        "-q",
        "-o",
        os,
        "--end-time",
        "6e-6",
        "--checkpoint-every",
        "5e-6",
    ]);
    let ckpt = out.join("restart.ckpt");
    let cs = ckpt.to_str().unwrap();
    let refused = |args: &[&str], what: &[&str]| {
        let r = cleave(args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        for w in what {
            assert!(err.contains(w), "{args:?}: {err} lacks {w}");
        }
    };
    // another deck: one material value changed
    let text = std::fs::read_to_string(&deck).unwrap();
    let other = d.join("other.k");
    let changed = text.replacen("8930.0", "8931.0", 1);
    assert_ne!(changed, text);
    std::fs::write(&other, changed).unwrap();
    let os2 = d.join("o2");
    let o2 = os2.to_str().unwrap();
    refused(
        &["run", other.to_str().unwrap(), "-o", o2, "--restart", cs],
        &["restart.ckpt", "differs"],
    );
    refused(
        &["run", &deck, "-o", os, "--restart", cs, "--no-separation"],
        &["--no-separation"],
    );
    // an end time the file is already past
    refused(
        &[
            "run",
            &deck,
            "-o",
            os,
            "--restart",
            cs,
            "--end-time",
            "1e-6",
        ],
        &["end time"],
    );
    // another version: the header's version string altered
    let bytes = std::fs::read(&ckpt).unwrap();
    let v = env!("CARGO_PKG_VERSION").as_bytes();
    let at = bytes.windows(v.len()).position(|w| w == v).unwrap();
    // each altered file is refused, with a message that says why
    let refused_file = |name: &str, bytes: &[u8], what: &str| {
        let f = d.join(name);
        std::fs::write(&f, bytes).unwrap();
        refused(
            &["run", &deck, "-o", os, "--restart", f.to_str().unwrap()],
            &[what],
        );
    };
    let mut old = bytes.clone();
    old[at] = b'9';
    refused_file("old.ckpt", &old, "made by cleave 9");
    // an earlier format: the number in the first line (the state's layout) changed
    let mut earlier = bytes.clone();
    assert!(earlier.starts_with(b"cleave restart file 3\n"));
    earlier[20] = b'2';
    refused_file(
        "earlier.ckpt",
        &earlier,
        "restart format 2, this one reads 3",
    );
    // damaged: cut short, or not a restart file at all
    refused_file(
        "cut.ckpt",
        &bytes[..bytes.len() / 2],
        "truncated or damaged",
    );
    refused(
        &["run", &deck, "-o", os, "--restart", &deck],
        &["not a cleave restart file"],
    );
    refused(
        &["run", &deck, "-o", os, "--checkpoint-every", "0"],
        &["--checkpoint-every"],
    );
}

/// A GPU run (`--gpu`; lavapipe where there is no GPU, which `.ci/run` installs) keeps the
/// device's state in its restart files: continued from the last one, or from the one written
/// when SIGTERM stopped it midway, it writes the same bytes as a GPU run never stopped. A CPU
/// run's file is refused by a GPU run, and the other way round, with a message that says so. A
/// file due at the end time is written, and a GPU run goes on from it as a CPU run from its own.
/// Without a device with f64 shaders the test says SKIPPED.
#[cfg(unix)]
#[test]
fn a_gpu_run_continues_from_its_restart_file() {
    let d = tmp("restart-gpu");
    let deck = example(&d, "taylor-bar", &[]);
    let probe = d.join("probe");
    let p = cleave(&[
        "run",
        &deck,
        "-q",
        "--gpu",
        "--end-time",
        "1e-6",
        "-o",
        probe.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&p.stderr);
    if p.status.code() == Some(1) && err.contains("--gpu:") {
        eprintln!("SKIPPED: {err}");
        return;
    }
    assert_eq!(p.status.code(), Some(0), "{err}");
    // restart files every 1.1e-5: one, then continued
    check_continuation(&d, &deck, "1.1e-5", &["--end-time", "2e-5", "--gpu"]);
    // continued to a later end time than the one it was made with
    let part = d.join("part");
    let ckpt = part.join("restart.ckpt");
    run_ok(&[
        "run",
        &deck,
        "-q",
        "--gpu",
        "-o",
        part.to_str().unwrap(),
        "--restart",
        ckpt.to_str().unwrap(),
        "--end-time",
        "2.5e-5",
    ]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(part.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "finished");
    let t = s["end_time"].as_f64().unwrap();
    assert!((t - 2.5e-5).abs() < 1e-12, "ended at {t}");

    // SIGTERM midway, in a run that halts for glstat at every step (a signal must be seen at
    // a halt too, not only after a batch that runs through)
    let text = std::fs::read_to_string(&deck).unwrap();
    let every_step = text.replace(
        "*DATABASE_GLSTAT\n$#      dt\n      5e-7",
        "*DATABASE_GLSTAT\n$#      dt\n      1e-9",
    );
    assert_ne!(text, every_step, "the glstat card of the Taylor bar deck");
    let deck = d.join("every-step.k").to_str().unwrap().to_string();
    std::fs::write(&deck, every_step).unwrap();
    let full = d.join("full-sig");
    let out = d.join("sig");
    let (fs, os) = (full.to_str().unwrap(), out.to_str().unwrap());
    run_ok(&["run", &deck, "-q", "--gpu", "--end-time", "3e-5", "-o", fs]);
    let child = spawn(&["run", &deck, "-q", "--gpu", "--end-time", "3e-5", "-o", os]);
    let err = terminate(child, &out);
    assert!(err.contains("--restart") && err.contains("--gpu"), "{err}");
    let ckpt = out.join("restart.ckpt");
    let cs = ckpt.to_str().unwrap();
    run_ok(&["run", &deck, "-q", "--gpu", "-o", os, "--restart", cs]);
    assert_same_output(&full, &out);

    // a GPU run's file is not a CPU run's, nor the other way round
    let cpu = d.join("cpu");
    let cpus = cpu.to_str().unwrap();
    let refused = |args: &[&str], want: &str| {
        let r = cleave(args);
        let e = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{e}");
        assert!(e.contains(want), "{e}");
    };
    refused(
        &["run", &deck, "-q", "-o", cpus, "--restart", cs],
        "continue it with --gpu",
    );
    run_ok(&[
        "run",
        &deck,
        "-q",
        "-o",
        cpus,
        "--end-time",
        "6e-6",
        "--checkpoint-every",
        "5e-6",
    ]);
    let cpu_ckpt = cpu.join("restart.ckpt");
    refused(
        &[
            "run",
            &deck,
            "-q",
            "--gpu",
            "-o",
            cpus,
            "--restart",
            cpu_ckpt.to_str().unwrap(),
        ],
        "continue it without --gpu",
    );

    // a restart file due at the end time is written, as on the CPU, and the run goes on from
    // it to a later end time as the CPU's does from its own (to round-off)
    let mut last_rows = Vec::new();
    let deck = d.join("deck.k").to_str().unwrap().to_string(); // the Taylor bar as written
    for (name, gpu) in [("end-cpu", false), ("end-gpu", true)] {
        let o = d.join(name);
        let os = o.to_str().unwrap();
        let mut args = vec!["run", &deck, "-q", "-o", os, "--end-time", "2e-6"];
        args.extend(["--checkpoint-every", "1e-6"]);
        args.extend(gpu.then_some("--gpu"));
        run_ok(&args);
        let ckpt = o.join("restart.ckpt");
        assert!(ckpt.exists(), "{name}: no restart file at the end time");
        let cs = ckpt.to_str().unwrap();
        let mut args = vec!["run", &deck, "-q", "-o", os, "--end-time", "3e-6"];
        args.extend(["--restart", cs]);
        args.extend(gpu.then_some("--gpu"));
        run_ok(&args);
        let (_, rows) = common::csv(&o.join("glstat.csv"));
        last_rows.push(rows.last().unwrap().clone());
    }
    let (c, g) = (&last_rows[0], &last_rows[1]);
    assert_eq!(c[0], 3e-6, "the continued runs end at 3e-6");
    for (a, b) in c.iter().zip(g) {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{c:?} vs {g:?}");
    }
}
