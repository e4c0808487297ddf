//! `cleave bench paper-tables [--end-time T] [--threads K] [-o DIR]`: the paper's Tables II
//! (no fracture) and III (fracture) for the six ball meshes of `cleave example ball-impact`.
//!
//! Each mesh runs twice, without and with the separation card, each in its own process
//! (`cleave bench ball --json`), so the peak memory is that run's. The window is the same
//! fixed span of simulated time for every run (default 50 us, [`super::ball::WINDOW`]: the
//! ball touches the plate at 1.3 us, so the impact, the contact and the first fractures are
//! inside it), not the paper's 10 ms: the time per element step is the figure of merit and it
//! does not need the whole 10 ms, which would take hours for the finest meshes. Written:
//! `DIR/paper-tables.md` (also printed) and `DIR/paper-tables.csv`, with the paper's figures
//! beside ours. Memory is the peak resident set of the process (the paper's "memory
//! required" counted the model's arrays only; ours includes the program, about 5 MB).

use std::fmt::Write as _;
use std::process::Command;

use crate::cli::BenchArgs;
use crate::example::ball_impact::BALL_SIZES;
use crate::failure::{io_failure, Failure};

use super::ball::{BallRun, WINDOW};

/// The paper's Table II (no fracture) and III (fracture): elements, nodes, memory (MB), time
/// per element step (us).
pub const PAPER_II: [(usize, usize, f64, f64); 6] = [
    (256, 321, 0.920, 17.1),
    (425, 520, 1.370, 16.5),
    (648, 779, 1.959, 15.5),
    (2800, 3137, 7.386, 14.2),
    (8775, 9504, 22.143, 13.9),
    (20000, 21271, 49.518, 14.8),
];
pub const PAPER_III: [(usize, usize, f64, f64); 6] = [
    (256, 2048, 3.327, 60.7),
    (425, 3400, 5.381, 54.4),
    (648, 5184, 8.076, 53.4),
    (2800, 22400, 33.847, 52.5),
    (8775, 70200, 105.04, 56.0),
    (20000, 160000, 238.66, 61.6),
];

/// One `cleave bench ball --json` run in a child process.
fn child(elements: usize, fracture: bool, a: &BenchArgs, end: f64) -> Result<BallRun, Failure> {
    let exe = std::env::current_exe()
        .map_err(|e| Failure::Other(format!("cannot find the cleave executable: {e}")))?;
    let mut cmd = Command::new(exe);
    cmd.args(["bench", "ball", "--json", "--elements"])
        .arg(elements.to_string())
        .arg("--end-time")
        .arg(end.to_string())
        .arg("--threads")
        .arg(a.threads.to_string());
    if !fracture {
        cmd.arg("--no-separation");
    }
    let out = cmd
        .output()
        .map_err(|e| Failure::Other(format!("cannot run cleave bench ball: {e}")))?;
    if !out.status.success() {
        return Err(Failure::Other(format!(
            "cleave bench ball --elements {elements} failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(text.trim())
        .ok()
        .and_then(|v| BallRun::from_json(&v))
        .ok_or_else(|| Failure::Other(format!("unreadable bench ball output: {text}")))
}

pub fn bench_paper_tables(a: &BenchArgs) -> Result<(), Failure> {
    let end = a.end_time.unwrap_or(WINDOW);
    let mut rows = Vec::new();
    for (k, &(elements, ..)) in BALL_SIZES.iter().enumerate() {
        for fracture in [false, true] {
            eprintln!(
                "paper-tables: {elements} elements, {}",
                if fracture { "fracture" } else { "no fracture" }
            );
            let r = child(elements, fracture, a, end)?;
            let paper = if fracture { PAPER_III[k] } else { PAPER_II[k] };
            rows.push((fracture, paper, r));
        }
    }
    let md = markdown(&rows, end, a.threads);
    let csv = csv(&rows);
    std::fs::create_dir_all(&a.output).map_err(|e| io_failure("cannot create", &a.output, e))?;
    for (name, text) in [("paper-tables.md", &md), ("paper-tables.csv", &csv)] {
        let path = a.output.join(name);
        std::fs::write(&path, text).map_err(|e| io_failure("cannot write", &path, e))?;
    }
    print!("{md}");
    Ok(())
}

type Row = (bool, (usize, usize, f64, f64), BallRun);

fn markdown(rows: &[Row], end: f64, threads: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Ball impact, {:.0} us of simulated time per run, {threads} thread(s); memory: peak resident set (MB); time: wall time of the step loop / (steps x elements), us. Paper: DYNA3D, 10 ms, 1999-era workstation.\n",
        end * 1e6
    );
    for (fracture, title) in [
        (false, "Table II: no fracture"),
        (true, "Table III: fracture"),
    ] {
        let _ = writeln!(s, "{title}\n");
        let _ = writeln!(
            s,
            "| elements | nodes | paper nodes | memory MB | paper MB | time us | paper us | contact share | failed interfaces |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        for (_, p, r) in rows.iter().filter(|r| r.0 == fracture) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1} | {:.3} | {:.3} | {:.1} | {:.0}% | {} |",
                r.ball_elements,
                r.ball_nodes,
                p.1,
                r.peak_rss_mb,
                p.2,
                r.us_per_element_step,
                p.3,
                100.0 * r.shares[2],
                r.failed_interfaces
            );
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "Fracture / no fracture\n");
    let _ = writeln!(
        s,
        "| elements | time ratio | paper time ratio | memory ratio | paper memory ratio |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for pair in rows.chunks(2) {
        if let [(_, p0, r0), (_, p1, r1)] = pair {
            let _ = writeln!(
                s,
                "| {} | {:.2} | {:.2} | {:.2} | {:.2} |",
                r0.ball_elements,
                r1.us_per_element_step / r0.us_per_element_step,
                p1.3 / p0.3,
                r1.peak_rss_mb / r0.peak_rss_mb,
                p1.2 / p0.2
            );
        }
    }
    let steal: Option<f64> = rows.iter().map(|r| r.2.steal).sum();
    if let Some(steal) = steal {
        let _ = writeln!(
            s,
            "\nHost steal time over the runs: {steal:.2} s{}",
            if steal > 0.0 {
                " (CPU time the host gave to other work: the runs with it are slower than the machine)"
            } else {
                ""
            }
        );
    }
    s
}

fn csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "fracture,elements,nodes,paper_nodes,steps,peak_rss_mb,paper_memory_mb,us_per_element_step,paper_us,share_elements,share_interfaces,share_contact,share_rest,failed_interfaces\n",
    );
    for (f, p, r) in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            u8::from(*f),
            r.ball_elements,
            r.ball_nodes,
            p.1,
            r.steps,
            r.peak_rss_mb,
            p.2,
            r.us_per_element_step,
            p.3,
            r.shares[0],
            r.shares[1],
            r.shares[2],
            r.shares[3],
            r.failed_interfaces
        );
    }
    s
}
