//! End-to-end tests that drive the `cleave` binary: exit codes and messages for bad input, a
//! numerical failure, and the output files of a small run (parsed back by their headers, and
//! the .vtu by an independent reader, Python's meshio, when it is installed).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{cleave, csv, tmp, BASE};

/// Asserts the exit code, showing stderr when it differs.
fn assert_exit(out: &Output, code: i32) {
    assert_eq!(
        out.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn write_deck(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("deck.k");
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `cleave run` on `text` and expects exit code 2 and a message containing every needle.
fn expect_bad(name: &str, text: &str, needles: &[&str]) {
    let d = tmp(name);
    let p = write_deck(&d, text);
    for cmd in ["check", "run"] {
        let out = cleave(
            &[cmd, p.to_str().unwrap(), "-q"]
                .into_iter()
                .filter(|a| cmd == "run" || *a != "-q")
                .collect::<Vec<_>>(),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{name} ({cmd}): exit {:?}, stderr: {err}",
            out.status.code()
        );
        assert!(!err.contains("panicked"), "{name}: {err}");
        for n in needles {
            assert!(
                err.contains(n),
                "{name} ({cmd}): message lacks '{n}': {err}"
            );
        }
    }
}

fn replace_line(text: &str, line: usize, new: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == line {
                new.to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn base_deck_checks_and_runs() {
    let d = tmp("base");
    let p = write_deck(&d, BASE);
    let out = cleave(&["check", p.to_str().unwrap()]);
    assert_exit(&out, 0);
    let out = cleave(&["run", p.to_str().unwrap(), "-q"]);
    assert_exit(&out, 0);
}

#[test]
fn non_numeric_field_names_line_and_field() {
    expect_bad(
        "nonnum",
        &replace_line(BASE, 19, "2,0.01x,0.0,0.0"),
        &["deck.k:19", "*NODE", "0.01x"],
    );
}

#[test]
fn missing_required_field_names_line() {
    expect_bad(
        "missing",
        &replace_line(BASE, 11, ",7800.0,2.0e11,0.3"),
        &["deck.k:11", "MID"],
    );
}

#[test]
fn undefined_node_names_id_and_line() {
    expect_bad(
        "undefnode",
        &replace_line(BASE, 32, "2,1,2,3,6,5,8,9,12,99"),
        &["deck.k:32", "99"],
    );
}

#[test]
fn duplicate_ids_are_named() {
    expect_bad(
        "dupnode",
        &replace_line(BASE, 19, "1,0.01,0.0,0.0"),
        &["1", "deck.k:19"],
    );
    expect_bad(
        "dupelem",
        &replace_line(BASE, 32, "1,1,2,3,6,5,8,9,12,11"),
        &["deck.k:32"],
    );
}

#[test]
fn inverted_element_is_named() {
    // swap the bottom and top faces: negative Jacobian at every corner
    expect_bad(
        "inverted",
        &replace_line(BASE, 32, "2,1,8,9,12,11,2,3,6,5"),
        &["element 2"],
    );
}

#[test]
fn bad_material_constants_are_rejected() {
    expect_bad(
        "density",
        &replace_line(BASE, 11, "1,0.0,2.0e11,0.3"),
        &["deck.k:11"],
    );
    expect_bad(
        "modulus",
        &replace_line(BASE, 11, "1,7800.0,-2.0e11,0.3"),
        &["deck.k:11"],
    );
    expect_bad(
        "poisson",
        &replace_line(BASE, 11, "1,7800.0,2.0e11,0.5"),
        &["deck.k:11"],
    );
    expect_bad(
        "poisson-neg",
        &replace_line(BASE, 11, "1,7800.0,2.0e11,-1.0"),
        &["deck.k:11"],
    );
}

#[test]
fn part_without_section_or_material() {
    expect_bad(
        "nosec",
        &replace_line(BASE, 16, "1,5,1"),
        &["deck.k:16", "5"],
    );
    expect_bad(
        "nomat",
        &replace_line(BASE, 16, "1,1,9"),
        &["deck.k:16", "9"],
    );
}

#[test]
fn unsorted_curve_is_rejected() {
    expect_bad(
        "curve",
        &replace_line(BASE, 36, "0.0,1.0"),
        &["7", "deck.k:36"],
    );
}

#[test]
fn unsupported_keyword_is_named() {
    expect_bad(
        "unsupported",
        &replace_line(BASE, 12, "*SECTION_SHELL"),
        &["deck.k:12", "*SECTION_SHELL"],
    );
}

#[test]
fn degenerate_files_exit_2_without_panic() {
    expect_bad("empty", "", &["deck.k"]);
    expect_bad("onlykeyword", "*KEYWORD\n", &["deck.k"]);
    let garbage: String = (0..2000u32)
        .map(|i| char::from_u32((i * 7919 + 13) % 0x2FF + 1).unwrap_or('x'))
        .collect();
    expect_bad("garbage", &garbage, &["deck.k"]);
    let d = tmp("binary");
    let p = d.join("deck.k");
    std::fs::write(
        &p,
        (0..4096u32)
            .map(|i| (i.wrapping_mul(2654435761) >> 24) as u8)
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    let out = cleave(&["run", p.to_str().unwrap(), "-q"]);
    assert_exit(&out, 2);
}

#[test]
fn missing_file_and_bad_options_exit_2() {
    let out = cleave(&["run", "/nonexistent/deck.k", "-q"]);
    assert_exit(&out, 2);
    let d = tmp("opts");
    let p = write_deck(&d, BASE);
    let out = cleave(&["run", p.to_str().unwrap(), "--end-time", "-1", "-q"]);
    assert_eq!(out.status.code(), Some(2));
    let out = cleave(&["run", p.to_str().unwrap(), "--threads", "0", "-q"]);
    assert_eq!(out.status.code(), Some(2));
}

/// The fragmenting bar's options: each bad value exits 2 naming the option; an option the
/// example does not take is named with the example.
#[test]
fn fragmenting_bar_options_are_checked() {
    let d = tmp("bar-opts");
    let deck = d.join("bar.k");
    let deck = deck.to_str().unwrap();
    for (args, needle) in [
        (vec!["--spread", "2"], "--spread 2"),
        (vec!["--spread", "0"], "--spread 0"),
        (vec!["--strain-rate", "0"], "--strain-rate"),
        (vec!["--elements", "1"], "--elements 1"),
    ] {
        let mut a = vec!["example", "fragmenting-bar", "-o", deck];
        a.extend(args);
        let out = cleave(&a);
        assert_exit(&out, 2);
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(needle),
            "{a:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let out = cleave(&["example", "taylor-bar", "-o", deck, "--strain-rate", "1"]);
    assert_exit(&out, 2);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("fragmenting-bar only, not to taylor-bar")
    );
    let out = cleave(&["bench", "fragmentation", "--rates", "1,x"]);
    assert_exit(&out, 2);
    assert!(String::from_utf8_lossy(&out.stderr).contains("'x'"));
    // a good one writes a deck that checks
    let out = cleave(&["example", "fragmenting-bar", "-o", deck, "--elements", "40"]);
    assert_exit(&out, 0);
    assert_exit(&cleave(&["check", deck]), 0);
}

/// A run that goes numerically wrong (the end pushed in at 10 km/s crushes an element inside
/// out within about 1 us) stops with exit code 3, names the element, the time and the step, and
/// leaves readable output.
#[test]
fn unstable_run_exits_3_with_readable_output() {
    let d = tmp("unstable");
    let text = BASE.replace("0.0,1.0\n1.0,1.0", "0.0,-1.0e4\n1.0,-1.0e4");
    let p = write_deck(&d, &text);
    let out = cleave(&["run", p.to_str().unwrap(), "-q"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("step") && err.contains("time"), "{err}");
    assert!(err.contains("element") || err.contains("node"), "{err}");
    let glstat = std::fs::read_to_string(d.join("deck.out/glstat.csv")).unwrap();
    assert!(
        glstat.lines().count() >= 2,
        "glstat has its header and the t = 0 row"
    );
    let summary = std::fs::read_to_string(d.join("deck.out/summary.json")).unwrap();
    assert!(summary.contains("\"steps\""));
}

/// The output files of the base run parse with the headers of the interface page, have a row
/// at t = 0 and at the end time, and the prescribed node moves at 1 m/s.
#[test]
fn outputs_parse_with_their_headers() {
    let d = tmp("outputs");
    let p = write_deck(&d, BASE);
    let out = cleave(&["run", p.to_str().unwrap(), "-q"]);
    assert_exit(&out, 0);
    let o = d.join("deck.out");
    let (h, rows) = csv(&o.join("glstat.csv"));
    assert_eq!(
        h.join(","),
        "time,dt,kinetic_energy,internal_energy,hourglass_energy,contact_energy,fracture_energy,external_work,total_energy,energy_ratio,failed_interfaces,fragments"
    );
    assert_eq!(rows[0][0], 0.0);
    assert!((rows.last().unwrap()[0] - 1e-5).abs() < 1e-15);
    let (h, rows) = csv(&o.join("nodout.csv"));
    assert_eq!(
        h.join(","),
        "time,node,x_disp,y_disp,z_disp,x_vel,y_vel,z_vel"
    );
    let last = rows.last().unwrap();
    assert_eq!(last[1], 3.0);
    assert!(
        (last[5] - 1.0).abs() < 1e-12,
        "prescribed velocity {}",
        last[5]
    );
    assert!(
        (last[2] - 1e-5).abs() < 1e-12,
        "displacement v t = {}",
        last[2]
    );
    let (h, _) = csv(&o.join("elout.csv"));
    assert_eq!(
        h.join(","),
        "time,element,sxx,syy,szz,sxy,syz,szx,eff_plastic_strain"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(o.join("summary.json")).unwrap()).unwrap();
    for k in [
        "elements",
        "nodes",
        "nodes_solved",
        "interfaces",
        "failed_interfaces",
        "fragments",
        "steps",
        "end_time",
        "wall_seconds",
        "us_per_element_step",
        "peak_rss_mb",
        "threads",
        "device",
        "energy_ratio",
        "version",
    ] {
        assert!(summary.get(k).is_some(), "summary.json lacks {k}");
    }
    assert_eq!(summary["elements"], 2);
    let png = std::fs::read(o.join("energy.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let pvd = std::fs::read_to_string(o.join("results.pvd")).unwrap();
    assert_eq!(
        pvd.matches("<DataSet").count(),
        2,
        "first and last state without *DATABASE_BINARY_D3PLOT"
    );

    // independent reader: meshio, when python3 has it
    let has_meshio = Command::new("python3")
        .args(["-c", "import meshio"])
        .status()
        .is_ok_and(|s| s.success());
    if !has_meshio {
        eprintln!(
            "SKIPPED outputs_parse_with_their_headers/meshio: python3 with meshio not available"
        );
        return;
    }
    let script = "import meshio,sys\nm=meshio.read(sys.argv[1])\nprint(len(m.points), sum(len(c.data) for c in m.cells), m.point_data['displacement'][2][0], m.cell_data['part'][0][1])";
    let vtu = o.join("states/state_00001.vtu");
    let py = Command::new("python3")
        .args(["-c", script, vtu.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&py.stdout);
    let vals: Vec<f64> = text
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(
        vals.len(),
        4,
        "meshio said: {text} {}",
        String::from_utf8_lossy(&py.stderr)
    );
    assert_eq!((vals[0], vals[1]), (12.0, 2.0));
    assert!(
        (vals[2] - 1e-5).abs() < 1e-12,
        "node 3 x displacement read by meshio: {}",
        vals[2]
    );
    assert_eq!(vals[3], 1.0);
}

/// A Gmsh fixture of cleave-io's tests (the hexahedral box, `gen.py` beside it).
fn gmsh_fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cleave-io/tests/data/gmsh")
        .join(name)
}

/// A deck that includes `mesh` and gives physical volume 1 a part, section and material.
fn gmsh_deck(mesh: &str) -> String {
    format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-6\n*INCLUDE\n{mesh}\n*PART\nblock\n1,1,1\n\
         *SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7800.0,2.0e11,0.3\n*BOUNDARY_SPC_SET\n2,0,1,1,1\n*END\n"
    )
}

#[test]
fn import_writes_keyword_text_that_a_deck_includes() {
    let d = tmp("gmsh-import");
    let k = d.join("hex.k");
    let msh = gmsh_fixture("hex-41b.msh");
    let out = cleave(&["import", msh.to_str().unwrap(), "-o", k.to_str().unwrap()]);
    assert_exit(&out, 0);
    let stdout = String::from_utf8_lossy(&out.stdout);
    for s in [
        "MSH 4.1 binary",
        "nodes 60",
        "solid elements 24 (hex8 24); 0 turned the right way out",
        "part 1 \"block\": hex8 24",
        "node set 2 (physical surface \"fixed\"): 12 nodes; segment set 2: 6 segments",
        "node set 4 (physical point \"tip\"): 1 nodes",
    ] {
        assert!(stdout.contains(s), "lacks '{s}': {stdout}");
    }
    let text = std::fs::read_to_string(&k).unwrap();
    // the header is the summary printed
    assert!(text.contains("$ part 1 \"block\": hex8 24"), "{text}");
    // the written text and the .msh itself, included in a deck, check the same
    for inc in [k.to_str().unwrap(), msh.to_str().unwrap()] {
        let deck = d.join("deck.k");
        std::fs::write(&deck, gmsh_deck(inc)).unwrap();
        let out = cleave(&["check", deck.to_str().unwrap()]);
        assert_exit(&out, 0);
        let s = String::from_utf8_lossy(&out.stdout);
        assert!(s.contains("elements    24"), "{s}");
        assert!(s.contains("nodes       60"), "{s}");
    }
}

#[test]
fn bad_meshes_exit_2_naming_file_and_line() {
    let d = tmp("gmsh-bad");
    let text = std::fs::read_to_string(gmsh_fixture("hex-22a.msh")).unwrap();
    // an element of the ASCII file that refers to node 999: its line named
    let (no, line) = text
        .lines()
        .enumerate()
        .find(|(_, l)| l.split(' ').nth(1) == Some("5"))
        .unwrap();
    let mut fields: Vec<&str> = line.split(' ').collect();
    let last = fields.len() - 1;
    fields[last] = "999";
    let bad = replace_line(&text, no + 1, &fields.join(" "));
    let msh = d.join("bad.msh");
    std::fs::write(&msh, bad).unwrap();
    let out = cleave(&["import", msh.to_str().unwrap()]);
    assert_exit(&out, 2);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("bad.msh:{}: ", no + 1)), "{err}");
    assert!(err.contains("node 999"), "{err}");
    assert!(!d.join("bad.k").exists());
    // the same through a deck's *INCLUDE, by `cleave check`
    let deck = d.join("deck.k");
    std::fs::write(&deck, gmsh_deck("bad.msh")).unwrap();
    let out = cleave(&["check", deck.to_str().unwrap()]);
    assert_exit(&out, 2);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("bad.msh:{}: ", no + 1)), "{err}");
    // a missing mesh, and a truncated binary one
    let out = cleave(&["import", d.join("none.msh").to_str().unwrap()]);
    assert_exit(&out, 2);
    let bin = std::fs::read(gmsh_fixture("hex-41b.msh")).unwrap();
    std::fs::write(&msh, &bin[..bin.len() / 2]).unwrap();
    let out = cleave(&["import", msh.to_str().unwrap()]);
    assert_exit(&out, 2);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.msh: byte "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `cleave check` lists what it read: the files (the Gmsh mesh the deck includes), every
/// keyword with its count, the warnings, each part's shapes and formulation, and whether
/// `--gpu` takes the deck.
#[test]
fn check_lists_files_keywords_and_the_shapes_of_each_part() {
    let deck = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/brazilian-disc/brazilian-disc.k");
    let out = cleave(&["check", deck.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("disc.msh (converted)"), "{text}");
    assert!(text.contains("*ELEMENT_SOLID x2"), "{text}");
    assert!(text.contains("warnings    none"), "{text}");
    assert!(
        text.contains("ELFORM 10: 4552 tetrahedra (one-point tetrahedron)"),
        "{text}"
    );
    assert!(
        text.contains("1 hexahedron (one-point hexahedron)"),
        "{text}"
    );
    // whether --gpu takes it: the disc's fragments meet the rigid platens by contact, whose
    // surfaces its cracks change
    assert!(text.contains("gpu         runs with --gpu"), "{text}");
    // the Taylor bar runs on the GPU
    let bar =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/taylor-bar.k");
    let out = cleave(&["check", bar.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("gpu         runs with --gpu"), "{text}");
}
