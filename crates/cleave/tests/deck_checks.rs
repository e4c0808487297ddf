//! Deck checks of issue 33: a rigid material's RO, E and PR are checked as every material's
//! are (exit 2 naming file, line, keyword and field), and a deck `cleave check` accepts is
//! not refused by `cleave run` (segment sets of contacts, the ParaView state cap): `check`
//! refuses it with `run`'s message.

mod common;

use common::{cleave, tmp, BASE};

/// Writes `text` to `dir/name` and returns the path as a string.
fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// Exit code and stderr of `cleave check DECK` and of `cleave run DECK -q -o DIR`.
fn check_and_run(deck: &str, out: &std::path::Path) -> [(Option<i32>, String); 2] {
    let c = cleave(&["check", deck]);
    let r = cleave(&["run", deck, "-q", "-o", out.to_str().unwrap()]);
    [c, r].map(|o| {
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    })
}

/// BASE made all rigid: its material `*MAT_RIGID` with `card`, a DTINIT (no deformable
/// element sets a step), and no prescribed nodal motion (a rigid body's nodes take only
/// `_RIGID`). Valid with `card` = `1,7800.0,2.0e11,0.3`.
fn rigid_deck(keyword: &str, card: &str) -> String {
    let old_mat = "*MAT_ELASTIC\n1,7800.0,2.0e11,0.3";
    let motion = BASE
        .find("*BOUNDARY_PRESCRIBED_MOTION_NODE")
        .expect("BASE has prescribed motion");
    let end = BASE.find("*END").unwrap();
    let t = format!("{}{}", &BASE[..motion], &BASE[end..]);
    assert!(t.contains(old_mat));
    t.replacen(old_mat, &format!("{keyword}\n{card}"), 1)
        .replacen(
            "*CONTROL_TERMINATION",
            "*CONTROL_TIMESTEP\n1.0e-7\n*CONTROL_TERMINATION",
            1,
        )
}

/// A rigid material with E negative, zero or blank, PR at or beyond (-1, 0.5), or RO not
/// positive is bad input for `check` and `run` alike (exit 2), the message naming the file,
/// the card's line (13: the card after `*MAT_RIGID`), the keyword and the field; it was
/// accepted (E and PR were not checked at all), and a negative E made the contact springs'
/// stiffness negative. The valid card still runs.
#[test]
fn a_rigid_material_with_a_bad_e_pr_or_density_is_refused() {
    let d = tmp("rigid-checks");
    for kw in ["*MAT_RIGID", "*MAT_020"] {
        let ok = write(&d, "ok.k", &rigid_deck(kw, "1,7800.0,2.0e11,0.3"));
        let [(c, ce), (r, re)] = check_and_run(&ok, &d.join("ok.out"));
        assert_eq!((c, r), (Some(0), Some(0)), "{ce}\n{re}");
        for (card, field, what) in [
            (
                "1,7800.0,-2.0e11,0.3",
                "E",
                "-200000000000 must be positive",
            ),
            ("1,7800.0,0.0,0.3", "E", "0 must be positive"),
            ("1,7800.0,,0.3", "E", "missing (must be positive)"),
            ("1,7800.0,2.0e11,0.5", "PR", "0.5 must lie in (-1, 0.5)"),
            ("1,7800.0,2.0e11,-1.0", "PR", "-1 must lie in (-1, 0.5)"),
            ("1,0.0,2.0e11,0.3", "RO", "0 must be positive"),
            ("1,-7800.0,2.0e11,0.3", "RO", "-7800 must be positive"),
        ] {
            let k = write(&d, "bad.k", &rigid_deck(kw, card));
            let want = format!("bad.k:13: {kw}: field {field}: {what}");
            for (cmd, (code, err)) in ["check", "run"]
                .iter()
                .zip(check_and_run(&k, &d.join("bad.out")))
            {
                assert_eq!(code, Some(2), "{cmd} {card}: {err}");
                assert!(err.contains(&want), "{cmd} {card}: want '{want}' in: {err}");
            }
        }
    }
}

/// A contact on a segment set (SSTYP 0) whose segment is no element face: `run` refuses it
/// when it builds the contact, and `check` used to accept it (it never built the contact).
/// Now both exit 2 with the same message naming the set and the segment's nodes; a segment
/// that is a face (1 2 5 4, element 1's face at z = 0) passes both.
#[test]
fn check_refuses_the_segment_set_run_refuses() {
    let d = tmp("segment-check");
    let deck = |seg: &str| {
        BASE.replacen(
            "*END",
            &format!("*SET_SEGMENT\n1\n{seg}\n*CONTACT_AUTOMATIC_SINGLE_SURFACE\n1,,0\n*END"),
            1,
        )
    };
    let ok = write(&d, "face.k", &deck("1,2,5,4"));
    let [(c, ce), (r, re)] = check_and_run(&ok, &d.join("face.out"));
    assert_eq!((c, r), (Some(0), Some(0)), "{ce}\n{re}");
    let bad = write(&d, "no-face.k", &deck("1,2,3,6"));
    let want = "error: segment set 1: segment 1 2 3 6 is not a face of any solid element";
    for (cmd, (code, err)) in ["check", "run"]
        .iter()
        .zip(check_and_run(&bad, &d.join("no-face.out")))
    {
        assert_eq!(code, Some(2), "{cmd}: {err}");
        assert!(err.contains(want), "{cmd}: {err}");
    }
}

/// More ParaView states than `run` writes (`*DATABASE_BINARY_D3PLOT` DT against ENDTIM) is
/// refused by `check` as by `run`, with the same message.
#[test]
fn check_refuses_the_state_count_run_refuses() {
    let d = tmp("state-cap-check");
    let k = write(
        &d,
        "states.k",
        &BASE.replacen(
            "*DATABASE_GLSTAT",
            "*DATABASE_BINARY_D3PLOT\n1e-12\n*DATABASE_GLSTAT",
            1,
        ),
    );
    let [(c, ce), (r, re)] = check_and_run(&k, &d.join("states.out"));
    assert_eq!((c, r), (Some(2), Some(2)), "{ce}\n{re}");
    let msg = |e: &str| {
        e.lines()
            .find(|l| l.starts_with("error:"))
            .unwrap()
            .to_string()
    };
    assert_eq!(msg(&ce), msg(&re));
    assert!(ce.contains("at most 10000"), "{ce}");
}
