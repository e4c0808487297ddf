//! Tests of the keyword deck reader and writer (`cleave_io::deck`).

use cleave_core::material::{JohnsonCook, PiecewiseLinear};
use cleave_core::mesh::BoxMesh;
use cleave_core::model::*;
use cleave_io::deck::{parse_deck, write_deck, DeckError};

/// A small deck using every supported keyword, in free format. Two elements along x: element
/// 1 (part 1, elastic with separation) and element 2 (part 2, rigid).
const BASE: &str = include_str!("all_keywords.k");

/// The same deck in fixed format: every comma-separated card right-aligned in the widths
/// the LS-DYNA manual gives for it.
fn to_fixed(free: &str) -> String {
    let mut out = String::new();
    let mut kw = String::new();
    let mut card_no = 0;
    for line in free.lines() {
        if line.starts_with('*') || line.starts_with('$') {
            if line.starts_with('*') {
                kw = line.to_string();
                card_no = 0;
            }
            out.push_str(line);
            out.push('\n');
            continue;
        }
        card_no += 1;
        if !line.contains(',') && kw != "*NODE" && kw != "*ELEMENT_SOLID" && kw != "*DEFINE_CURVE" {
            // a single value (or a title): one 10-character field, titles left as they are
            let is_title = line.replace(['d', 'D'], "e").parse::<f64>().is_err();
            if is_title {
                out.push_str(line);
            } else {
                out.push_str(&format!("{:>10}", line.trim()));
            }
            out.push('\n');
            continue;
        }
        let widths: Vec<usize> = match kw.as_str() {
            "*NODE" => vec![8, 16, 16, 16, 8, 8],
            "*ELEMENT_SOLID" => vec![8; 10],
            "*DEFINE_CURVE" if card_no > 1 => vec![20, 20],
            _ => vec![10; 8],
        };
        for (f, w) in line.split(',').zip(widths) {
            out.push_str(&format!("{:>w$}", f.trim()));
        }
        out.push('\n');
    }
    out
}

fn parse(text: &str) -> Model {
    match parse_deck(text, "t.k") {
        Ok(d) => d.model,
        Err(e) => panic!("{e}"),
    }
}

fn err(text: &str) -> DeckError {
    match parse_deck(text, "t.k") {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// 1-based number of the first line containing `s`.
/// (A line equal to `s` is preferred; a multi-line `s` gives the line where it starts.)
fn line_of(text: &str, s: &str) -> usize {
    if s.contains('\n') {
        return text[..text.find(s).expect(s)].lines().count() + 1;
    }
    let exact = text.lines().position(|l| l.trim() == s.trim());
    exact
        .or_else(|| text.lines().position(|l| l.contains(s)))
        .expect(s)
        + 1
}

/// BASE with the first occurrence of `old` replaced by `new`.
fn with(old: &str, new: &str) -> String {
    assert!(BASE.contains(old), "{old}");
    BASE.replacen(old, new, 1)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn base_deck_is_read_completely() {
    let m = parse(BASE);
    assert_eq!(m.title, "two bricks");
    assert_eq!(m.num_nodes(), 12);
    assert_eq!(m.elem_ids, vec![1, 2]);
    assert_eq!(m.conn[0], [0, 1, 4, 3, 6, 7, 10, 9]);
    assert_eq!(m.conn[1], [1, 2, 5, 4, 7, 8, 11, 10]);
    assert_eq!(m.elem_part, vec![0, 1]);
    assert_eq!(m.parts[1].title, "plate");
    assert_eq!(
        m.materials[1].kind,
        MaterialKind::Rigid {
            cmo: 1,
            con1: 4,
            con2: 7
        }
    );
    assert_eq!(m.separations.len(), 1);
    let s = &m.separations[0];
    assert_eq!(
        (s.material, s.model, s.sigmax, s.beta, s.gc, s.bond),
        (0, 2, 1e8, 0.5, 0.0, 1)
    );
    let c = &m.control;
    assert_eq!(
        (c.end_time, c.tssfac, c.hourglass, c.qh),
        (1e-3, 0.8, Hourglass::Stiffness, 0.05)
    );
    assert_eq!((c.q1, c.q2, c.slsfac), (1.2, 0.05, 0.2));
    assert_eq!(c.penalty, PenaltyRule::Smaller); // PENOPT blank: 1
    let t = with("*CONTROL_CONTACT\n0.2\n", "*CONTROL_CONTACT\n0.2,,,,2\n");
    assert_eq!(parse(&t).control.penalty, PenaltyRule::Face);
    assert_eq!(
        (m.output.glstat_dt, m.output.nodout_dt, m.output.d3plot_dt),
        (1e-5, 2e-5, 1e-4)
    );
    assert_eq!(m.output.history_nodes, vec![0, 11]);
    assert_eq!(m.output.history_solids, vec![1]);
    assert_eq!(m.node_sets[0].nodes, vec![0, 3, 6, 9]);
    assert_eq!(m.part_sets[0].parts, vec![0, 1]);
    assert_eq!(m.segment_sets[0].segments, vec![[0, 3, 9, 6], [0, 1, 7, 7]]);
    // curve 1: SFO 2 doubles the ordinates
    assert_eq!(m.curves[0].y, vec![0.0, 2.0]);
    // SPCs merged per node: node 1 from the set (x) and the node card (y, z); node 4 from
    // the set and TC = 3; node 12 from RC = 7
    let spc = |i: u32| m.spcs.iter().find(|s| s.node == i).map(|s| s.dof);
    assert_eq!(spc(0), Some([true, true, true, false, false, false]));
    assert_eq!(spc(3), Some([true, false, true, false, false, false]));
    assert_eq!(spc(11), Some([false, false, false, true, true, true]));
    assert!(m.spcs.windows(2).all(|w| w[0].node < w[1].node));
    assert_eq!(m.prescribed.len(), 1 + 4);
    assert_eq!(m.prescribed[0].target, MotionTarget::Rigid(1));
    assert_eq!(
        (m.prescribed[0].dof, m.prescribed[0].sf),
        (MotionDof::Axis(0), 0.5)
    );
    assert_eq!(m.prescribed[1].target, MotionTarget::Node(0));
    assert_eq!(
        (
            m.prescribed[1].dof,
            m.prescribed[1].vad,
            m.prescribed[1].curve,
            m.prescribed[1].sf
        ),
        (MotionDof::Axis(2), Vad::Displacement, 1, 1.0)
    );
    assert_eq!(
        m.body_loads,
        vec![BodyLoad {
            axis: 2,
            curve: None,
            sf: 9.81
        }]
    );
    assert_eq!(m.rigid_walls.len(), 2);
    assert_eq!(m.rigid_walls[0].nodes, None);
    assert_eq!(m.rigid_walls[1].nodes, Some(vec![0, 3, 6, 9]));
    assert_eq!((m.rigid_walls[1].id, m.rigid_walls[1].fric), (2, 0.0));
    assert_eq!(m.contacts[0].slave, ContactSurface::PartSet(0));
    assert_eq!(
        (m.contacts[0].fs, m.contacts[0].fd, m.contacts[0].dc),
        (0.3, 0.2, 0.0)
    );
    assert_eq!(m.contacts[1].master, Some(ContactSurface::Part(1)));
    assert!(!m.contacts[1].single_surface);
}

#[test]
fn fixed_and_free_format_agree() {
    let fixed = to_fixed(BASE);
    assert!(!fixed.lines().any(|l| l.contains(',')));
    assert_eq!(format!("{:?}", parse(&fixed)), format!("{:?}", parse(BASE)));
}

#[test]
fn crlf_lowercase_and_trailing_blanks_are_accepted() {
    let t = BASE
        .to_lowercase()
        .replace("two bricks", "Two Bricks")
        .replace('\n', "  \r\n");
    let m = parse(&t);
    assert_eq!(m.title, "Two Bricks");
    assert_eq!(
        format!("{:?}", m),
        format!("{:?}", {
            let mut b = parse(BASE);
            b.title = "Two Bricks".into();
            b
        })
    );
}

#[test]
fn one_card_and_two_card_elements_agree() {
    let two = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10\n",
        "1, 1\n1, 2, 5, 4, 7, 8, 11, 10\n",
    );
    let one = with("2, 2\n2, 3, 6, 5", "2, 2, 2, 3, 6, 5");
    let a = format!("{:?}", parse(BASE));
    assert_eq!(format!("{:?}", parse(&two)), a);
    assert_eq!(format!("{:?}", parse(&one)), a);
    assert_eq!(format!("{:?}", parse(&to_fixed(&two))), a);
    assert_eq!(format!("{:?}", parse(&to_fixed(&one))), a);
}

#[test]
fn defaults_are_applied() {
    let t = BASE
        .replace("*CONTROL_TIMESTEP\n0.0, 0.8\n", "")
        .replace("*CONTROL_HOURGLASS\n4, 0.05\n", "*CONTROL_HOURGLASS\n\n")
        .replace(
            "*CONTROL_BULK_VISCOSITY\n1.2, 0.05\n",
            "*CONTROL_BULK_VISCOSITY\n0, \n",
        )
        .replace("*CONTROL_CONTACT\n0.2\n", "")
        .replace("1, 2, 1.0e8, 0.5", "1, 1, 1.0e8")
        .replace("2, 1, 0, 1, 0.5", "2, 1, 0, 1");
    let m = parse(&t);
    let c = &m.control;
    assert_eq!(
        (c.dt_init, c.tssfac, c.hourglass, c.qh),
        (0.0, 0.9, Hourglass::Viscous, 0.1)
    );
    assert_eq!((c.q1, c.q2, c.slsfac), (1.5, 0.06, 0.1));
    assert_eq!((m.separations[0].beta, m.separations[0].bond), (1.0, 1));
    assert_eq!(m.prescribed[0].sf, 1.0);
    let m = parse(&t.replace("1, 1, 1.0e8", "1, 1, 1.0e8, , , 0"));
    assert_eq!(m.separations[0].bond, 0);
}

#[test]
fn curve_scaling_and_offsets() {
    let t = with(
        "1, 0, 0., 2.0\n0., 0.\n1.0e-3, 1.\n",
        "1, 0, 1000., 2.0, 1., -1.\n0., 0.\n1.0e-3, 1.\n2.0e-3, 5.\n",
    );
    let c = &parse(&t).curves[0];
    assert_eq!(c.t, vec![1.0, 2.0, 3.0]);
    assert_eq!(c.y, vec![-1.0, 1.0, 9.0]);
}

#[test]
fn initial_velocity_generation_rotates() {
    let m = parse(BASE);
    // part 1: nodes of element 1; v = (1,0,0) + 10 z x r
    for &i in &m.conn[0] {
        let x = m.x0[i as usize];
        let v = m.v0[i as usize];
        assert!(close(v[0], 1.0 - 10.0 * x[1]), "{v:?} at {x:?}");
        assert!(close(v[1], 10.0 * x[0]));
        assert_eq!(v[2], 0.0);
    }
    // node 3 (x=2, y=0) is only in part 2
    assert_eq!(m.v0[2], [0.0; 3]);
    // a later *INITIAL_VELOCITY_NODE overrides; rotation about an axis through (1, 1, 0)
    let t = with(
        "0., 0., 0., 0., 0., 2.\n",
        "1., 1., 0., 0., 0., 2.\n*INITIAL_VELOCITY_NODE\n5, 0., 0., 3.\n",
    );
    let m = parse(&t);
    assert_eq!(m.v0[4], [0.0, 0.0, 3.0]);
    // node 1 at (0,0,0): r = (-1,-1,0), w x r = 10 (1, -1, 0)
    assert!(close(m.v0[0][0], 1.0 + 10.0) && close(m.v0[0][1], -10.0));
}

#[test]
fn warnings_for_title_free_unknown_database() {
    let t = with(
        "*DATABASE_GLSTAT",
        "*DATABASE_MATSUM\n1e-5\n*DATABASE_GLSTAT",
    );
    let d = parse_deck(&t, "t.k").unwrap();
    assert_eq!(d.warnings.len(), 1, "{:?}", d.warnings);
    assert!(d.warnings[0].contains("*DATABASE_MATSUM"));
}

// ---------------------------------------------------------------------------------------
// errors

/// Checks an error's line, keyword and field, and that its message contains `msg`.
fn check(e: &DeckError, line: Option<usize>, kw: Option<&str>, field: Option<&str>, msg: &str) {
    assert_eq!(e.file, "t.k");
    assert_eq!(e.line, line, "{e}");
    assert_eq!(e.keyword.as_deref(), kw, "{e}");
    assert_eq!(e.field.as_deref(), field, "{e}");
    assert!(e.message.contains(msg), "{e}");
    assert!(e.to_string().contains(msg));
}

#[test]
fn non_numeric_field() {
    let t = with("5, 1., 1., 0.", "5, 1., abc, 0.");
    let e = err(&t);
    check(
        &e,
        Some(line_of(&t, "abc")),
        Some("*NODE"),
        Some("Y"),
        "'abc' is not a number",
    );
    assert_eq!(
        e.to_string(),
        format!(
            "t.k:{}: *NODE: field Y: 'abc' is not a number",
            line_of(&t, "abc")
        )
    );
    // the same in fixed format
    let f = to_fixed(&t);
    let e = err(&f);
    check(
        &e,
        Some(line_of(&f, "abc")),
        Some("*NODE"),
        Some("Y"),
        "'abc' is not a number",
    );
    for bad in ["nan", "inf", "1e999", "1.0.0"] {
        let t = with("5, 1., 1., 0.", &format!("5, 1., {bad}, 0."));
        assert_eq!(err(&t).field.as_deref(), Some("Y"), "{bad}");
    }
}

#[test]
fn missing_required_and_fractional_ids() {
    let t = with("2, 1, 2\n", " , 1, 2\n");
    check(
        &err(&t),
        Some(line_of(&t, " , 1, 2")),
        Some("*PART"),
        Some("PID"),
        "missing",
    );
    let t = with("2, 1, 2\n", "2, 1.5, 2\n");
    check(
        &err(&t),
        Some(line_of(&t, "2, 1.5, 2")),
        Some("*PART"),
        Some("SECID"),
        "'1.5' is not an integer",
    );
    let t = with("2, 1, 2\n", "2, 1, \n");
    check(
        &err(&t),
        Some(line_of(&t, "2, 1, ")),
        Some("*PART"),
        Some("MID"),
        "no material",
    );
    let t = with("2, 1, 2\n", "2, , 2\n");
    check(
        &err(&t),
        Some(line_of(&t, "2, , 2")),
        Some("*PART"),
        Some("SECID"),
        "no section",
    );
}

#[test]
fn undefined_references() {
    let cases: &[(&str, &str, &str, &str, &str)] = &[
        (
            "2, 3, 6, 5, 8, 9, 12, 11",
            "2, 3, 99, 5, 8, 9, 12, 11",
            "*ELEMENT_SOLID",
            "N3",
            "node 99 is not defined",
        ),
        (
            "2, 2\n",
            "2, 7\n",
            "*ELEMENT_SOLID",
            "PID",
            "part 7 is not defined",
        ),
        (
            "2, 1, 2\n",
            "2, 1, 9\n",
            "*PART",
            "MID",
            "material 9 is not defined",
        ),
        (
            "2, 1, 2\n",
            "2, 4, 2\n",
            "*PART",
            "SECID",
            "section 4 is not defined",
        ),
        (
            "1, 0, 1\n",
            "8, 0, 1\n",
            "*BOUNDARY_SPC_SET",
            "NSID",
            "node set 8 is not defined",
        ),
        (
            "2, 1, 0, 1, 0.5",
            "2, 1, 0, 6, 0.5",
            "*BOUNDARY_PRESCRIBED_MOTION_RIGID",
            "LCID",
            "curve 6 is not defined",
        ),
        (
            "1, 12\n",
            "1, 13\n",
            "*DATABASE_HISTORY_NODE",
            "ID",
            "node 13 is not defined",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "3, 2, 1.0e8, 0.5",
            "*MAT_ADD_SEPARATION",
            "MID",
            "material 3 is not defined",
        ),
        (
            "5, 0, 2\n",
            "6, 0, 2\n",
            "*CONTACT_AUTOMATIC_SINGLE_SURFACE",
            "SSID",
            "part set 6 is not defined",
        ),
        (
            "1, 2, 3, 3\n",
            "1, 3, 3, 3\n",
            "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
            "MSID",
            "part 3 is not defined",
        ),
        (
            "1, 4, 7, 10, 0, 1",
            "1, 4, 7, 10, 0, 31",
            "*SET_NODE_LIST",
            "NID",
            "node 31 is not defined",
        ),
        (
            "1, 2, 10., 1.",
            "9, 2, 10., 1.",
            "*INITIAL_VELOCITY_GENERATION",
            "ID",
            "part 9 is not defined",
        ),
        (
            "0, 9.81",
            "3, 9.81",
            "*LOAD_BODY_Z",
            "LCID",
            "curve 3 is not defined",
        ),
    ];
    for &(old, new, kw, field, msg) in cases {
        let t = with(old, new);
        check(
            &err(&t),
            Some(line_of(&t, new.trim_end())),
            Some(kw),
            Some(field),
            msg,
        );
    }
}

#[test]
fn duplicate_ids_name_both_lines() {
    // (old, new, first definition, second definition, message); a definition is a marker
    // (see `line_of`) and a line offset from it
    type At = (&'static str, usize);
    let cases: &[(&str, &str, At, At, &str)] = &[
        (
            "12, 2., 1., 1., 0, 7\n",
            "12, 2., 1., 1., 0, 7\n7, 5., 5., 5.\n",
            ("7, 0., 0., 1.", 0),
            ("7, 5., 5., 5.", 0),
            "node 7",
        ),
        (
            "2, 2\n",
            "1, 2\n",
            ("*ELEMENT_SOLID", 1),
            ("*ELEMENT_SOLID", 2),
            "element 1",
        ),
        (
            "2, 1, 2\n",
            "1, 1, 2\n",
            ("*PART", 2),
            ("1, 1, 2", 0),
            "part 1",
        ),
        (
            "2, 7800., 2.0e11, 0.3\n",
            "1, 7800., 2.0e11, 0.3\n",
            ("*MAT_ELASTIC", 1),
            ("*MAT_RIGID", 1),
            "material 1",
        ),
        (
            "*DEFINE_CURVE\n2\n",
            "*DEFINE_CURVE\n1\n",
            ("*DEFINE_CURVE", 1),
            ("*DEFINE_CURVE\n1\n", 1),
            "curve 1",
        ),
        (
            "*SET_PART_LIST\n5\n",
            "*SET_SEGMENT\n3\n*SET_PART_LIST\n5\n",
            ("*SET_SEGMENT", 1),
            ("*SET_SEGMENT\n3\n1, 4", 1),
            "segment set 3",
        ),
        (
            "*SET_PART_LIST\n5\n",
            "*SET_NODE_LIST\n1\n*SET_PART_LIST\n5\n",
            ("*SET_NODE_LIST", 1),
            ("*SET_NODE_LIST\n1\n*SET_PART", 1),
            "node set 1",
        ),
        (
            "*SET_SEGMENT\n3\n",
            "*SET_PART_LIST\n5\n*SET_SEGMENT\n3\n",
            ("*SET_PART_LIST", 1),
            ("*SET_PART_LIST\n5\n*SET_SEG", 1),
            "part set 5",
        ),
        (
            "1, 1\n*MAT_ELASTIC",
            "1, 1\n1, 1\n*MAT_ELASTIC",
            ("*SECTION_SOLID", 1),
            ("*SECTION_SOLID", 2),
            "section 1",
        ),
    ];
    for &(old, new, first, second, msg) in cases {
        let t = with(old, new);
        let e = err(&t);
        let (l1, l2) = (
            line_of(&t, first.0) + first.1,
            line_of(&t, second.0) + second.1,
        );
        assert_eq!(e.line, Some(l2), "{e}");
        let want = format!("{msg} is defined twice (first at line {l1})");
        assert!(e.message.contains(&want), "{e} / {want}");
    }
}

#[test]
fn an_element_stretched_beyond_any_mesh_is_rejected() {
    // node 7's z typed as 1.0e10 for 1.0: element 1 (its line) spans 1e10 in z and 1 in x
    let t = with("7, 0., 0., 1.", "7, 0., 0., 1.0e10");
    let e = err(&t);
    assert_eq!(e.line, Some(line_of(&t, "1, 1, 1, 2, 5, 4")), "{e}");
    assert!(
        e.message.contains("element 1: its longest edge (1.000e10, nodes 1 and 7) is more than 1e6 times its shortest (1.000e0)"),
        "{e}"
    );
    // a long thin element of aspect 1e5 is taken
    parse(
        &with("7, 0., 0., 1.", "7, 0., 0., 1.0e5")
            .replace("11, 1., 1., 1.", "11, 1., 1., 1.0e5")
            .replace("8, 1., 0., 1.", "8, 1., 0., 1.0e5")
            .replace("10, 0., 1., 1.", "10, 0., 1., 1.0e5"),
    );
}

#[test]
fn inverted_element_is_rejected() {
    let t = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10",
        "1, 1, 2, 1, 5, 4, 7, 8, 11, 10",
    );
    check(
        &err(&t),
        Some(line_of(&t, "1, 1, 2, 1, 5")),
        Some("*ELEMENT_SOLID"),
        None,
        "element 1 has a non-positive Jacobian",
    );
    // a hexahedron collapsed in a pattern that is no wedge or tetrahedron
    let t = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10",
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 11",
    );
    check(
        &err(&t),
        Some(line_of(&t, "1, 1, 1, 2, 5, 4, 7, 8, 11, 11")),
        Some("*ELEMENT_SOLID"),
        None,
        "repeated nodes in a pattern cleave does not take",
    );
    // a tetrahedron N1 N2 N3 N4 N4 N4 N4 N4 is read; turned inside out it is an error
    let t = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10",
        "1, 1, 1, 2, 4, 7, 7, 7, 7, 7",
    );
    let d = parse_deck(&t, "t.k").unwrap();
    assert_eq!(
        d.model.conn[0][2], d.model.conn[0][3],
        "stored N1 N2 N3 N3 N4.."
    );
    // the same tetrahedron with N5..N8 blank (LS-PrePost's 4-node form), in free format and
    // in fixed 8-column fields, reads the same
    for tet4 in [
        "1, 1, 1, 2, 4, 7",
        "       1       1       1       2       4       7",
    ] {
        let t4 = with("1, 1, 1, 2, 5, 4, 7, 8, 11, 10", tet4);
        assert_eq!(
            parse_deck(&t4, "t.k").unwrap().model.conn,
            d.model.conn,
            "{tet4}"
        );
    }
    // some of N5..N8 blank but not all: an error naming the first
    let t = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10",
        "       1       1       1       2       4       7       7",
    );
    let e = err(&t);
    assert_eq!(e.field.as_deref(), Some("N6"), "{e}");
    let t = with(
        "1, 1, 1, 2, 5, 4, 7, 8, 11, 10",
        "1, 1, 2, 1, 4, 7, 7, 7, 7, 7",
    );
    check(
        &err(&t),
        Some(line_of(&t, "1, 1, 2, 1, 4, 7")),
        Some("*ELEMENT_SOLID"),
        None,
        "tetrahedron 1 is inverted or flat",
    );
}

#[test]
fn material_values_are_checked() {
    let cases: &[(&str, &str, &str)] = &[
        ("1, 7800., 2.0e11, 0.3", "1, 0., 2.0e11, 0.3", "RO"),
        ("1, 7800., 2.0e11, 0.3", "1, 7800., -2.0e11, 0.3", "E"),
        ("1, 7800., 2.0e11, 0.3", "1, 7800., 2.0e11, 0.5", "PR"),
        ("1, 7800., 2.0e11, 0.3", "1, 7800., 2.0e11, -1.0", "PR"),
        ("2, 7800., 2.0e11, 0.3", "2, -1., 2.0e11, 0.3", "RO"),
        // rigid: E and PR checked too (they set the contact stiffness; issue 33)
        ("2, 7800., 2.0e11, 0.3", "2, 7800., 0., 0.3", "E"),
        ("2, 7800., 2.0e11, 0.3", "2, 7800., -2.0e11, 0.3", "E"),
        ("2, 7800., 2.0e11, 0.3", "2, 7800., 2.0e11, 0.7", "PR"),
    ];
    for &(old, new, field) in cases {
        let t = with(old, new);
        let e = err(&t);
        check(
            &e,
            Some(line_of(&t, new)),
            e.keyword.as_deref(),
            Some(field),
            "",
        );
    }
    // plastic kinematic
    let pk = |card: &str| {
        BASE.replacen(
            "*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3",
            &format!("*MAT_PLASTIC_KINEMATIC\n{card}"),
            1,
        )
    };
    let m = parse(&pk("1, 7800., 2.0e11, 0.3, 2.5e8, 1.0e9, 1."));
    assert_eq!(
        m.materials[0].kind,
        MaterialKind::PlasticKinematic {
            sigy: 2.5e8,
            etan: 1e9,
            beta: 1.0
        }
    );
    assert_eq!(
        err(&pk("1, 7800., 2.0e11, 0.3, 0., 1.0e9"))
            .field
            .as_deref(),
        Some("SIGY")
    );
    assert_eq!(
        err(&pk("1, 7800., 2.0e11, 0.3, 1e8, 3.0e11"))
            .field
            .as_deref(),
        Some("ETAN")
    );
}

#[test]
fn unsupported_options_are_errors() {
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "2, 1, 0, 1, 0.5",
            "2, 9, 0, 1, 0.5",
            "DOF",
            "9 not supported",
        ),
        ("2, 1, 0, 1, 0.5", "2, 1, 1, 1, 0.5", "VAD", "not supported"),
        ("4, 0.05", "6, 0.05", "IHQ", "not supported"),
        (
            "*CONTROL_CONTACT\n0.2\n",
            "*CONTROL_CONTACT\n0.2, 0, 0, 0, 4\n",
            "PENOPT",
            "not supported",
        ),
        (
            "*SECTION_SOLID\n1, 1",
            "*SECTION_SOLID\n1, 3",
            "ELFORM",
            "3 not supported",
        ),
        (
            "0., 0., 0., 0., 0., 2.",
            "0., 0., 0., 0., 0., 0.",
            "NX",
            "axis",
        ),
        ("1, 2, 1.0e8, 0.5", "1, 3, 1.0e8, 0.5", "GC", "missing"),
        ("1, 2, 1.0e8, 0.5", "1, 4, 1.0e8, 0.5", "GC", "missing"),
        ("1, 2, 1.0e8, 0.5", "1, 5, 1.0e8, 0.5", "MODEL", "5"),
        ("1, 2, 1.0e8, 0.5", "1, 2, 1.0e8, 0.5, , , 3", "DIST", "3"),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, 1.0e8, 0.5, , , 2",
            "",
            "missing card (SMIN SMAX M AREF)",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, , 0.5, , , 1, 7\n2.0e8, 1.0e8",
            "SMAX",
            "must exceed SMIN",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, 1.0e8, 0.5, , , 2, 7\n0., , 0., 1e-4",
            "M",
            "must be positive",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, 1.0e8, 0.5, , , 2, 7\n0., 3.0e8, 6., 1e-4",
            "SMAX",
            "DIST 1 (uniform) only",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, 1.0e8, 0.5, , , 1, 7\n0., 3.0e8, 6.",
            "M",
            "DIST 2 (Weibull) only",
        ),
        (
            "1, 2, 1.0e8, 0.5",
            "1, 2, 1.0e8, 0.5, , , 2, 7\n0., , 6., -1e-4",
            "AREF",
            "no size scaling",
        ),
        (
            "-1., 0., 0., 0., 0., 0.",
            "0., 0., 0., 0., 0., 0.",
            "XH",
            "head",
        ),
        (
            "1, 4, 10, 7\n",
            "1, 4, 10, 7\n1, 2, 5, 4, 7, 8, 11, 10, 12\n",
            "",
            "too many fields",
        ),
    ];
    for &(old, new, field, msg) in cases {
        let t = with(old, new);
        let e = err(&t);
        let last = new.lines().last().unwrap();
        assert_eq!(e.line, Some(line_of(&t, last)), "{e}");
        if !field.is_empty() {
            assert_eq!(e.field.as_deref(), Some(field), "{e}");
        }
        assert!(e.message.contains(msg), "{e}");
    }
    // _RIGID on a deformable part
    let t = with("2, 1, 0, 1, 0.5", "1, 1, 0, 1, 0.5");
    check(
        &err(&t),
        Some(line_of(&t, "1, 1, 0, 1, 0.5")),
        Some("*BOUNDARY_PRESCRIBED_MOTION_RIGID"),
        Some("PID"),
        "part 1 is not rigid",
    );
}

#[test]
fn unsorted_curve() {
    let t = with("1.0e-3, 1.\n", "1.0e-3, 1.\n1.0e-3, 2.\n");
    let e = err(&t);
    check(
        &e,
        Some(line_of(&t, "1.0e-3, 2.")),
        Some("*DEFINE_CURVE"),
        Some("A"),
        "curve 1",
    );
    assert!(e.message.contains("strictly increasing"));
    let t = with("*DEFINE_CURVE\n2\n0., 1.\n", "*DEFINE_CURVE\n2\n");
    check(
        &err(&t),
        Some(line_of(&t, "*DEFINE_CURVE\n2\n") + 1),
        Some("*DEFINE_CURVE"),
        None,
        "curve 2 has no points",
    );
}

#[test]
fn unsupported_keyword() {
    let t = with("*MAT_ELASTIC", "*MAT_SOIL_AND_FOAM\n1, 2\n*MAT_ELASTIC");
    let e = err(&t);
    check(
        &e,
        Some(line_of(&t, "*MAT_SOIL_AND_FOAM")),
        Some("*MAT_SOIL_AND_FOAM"),
        None,
        "not supported",
    );
    let t = with(
        "*CONTROL_CONTACT",
        "*CONTROL_DYNAMIC_RELAXATION\n2\n*CONTROL_CONTACT",
    );
    check(
        &err(&t),
        Some(line_of(&t, "*CONTROL_DYNAMIC_RELAXATION")),
        Some("*CONTROL_DYNAMIC_RELAXATION"),
        None,
        "not supported",
    );
}

#[test]
fn whole_deck_errors() {
    check(&err(""), None, None, None, "empty");
    check(&err("  \n$ only a comment\n"), None, None, None, "");
    check(&err("*KEYWORD\n"), None, None, None, "no elements");
    check(&err("*KEYWORD\n*END\n"), None, None, None, "");
    check(
        &err("1, 2, 3\n*KEYWORD\n"),
        Some(1),
        None,
        None,
        "before the first keyword",
    );
    let t = BASE
        .replacen(
            "*ELEMENT_SOLID\n1, 1, 1, 2, 5, 4, 7, 8, 11, 10\n2, 2\n2, 3, 6, 5, 8, 9, 12, 11\n",
            "",
            1,
        )
        .replace("2\n*PART", "*PART")
        .replace("*DATABASE_HISTORY_SOLID\n", "");
    check(&err(&t), None, None, None, "no elements");
    let t = with("*CONTROL_TERMINATION\n1.0e-3\n", "");
    check(&err(&t), None, None, None, "ENDTIM");
    let t = with(
        "*CONTROL_TERMINATION\n1.0e-3\n",
        "*CONTROL_TERMINATION\n0.\n",
    );
    check(
        &err(&t),
        Some(line_of(&t, "*CONTROL_TERMINATION") + 1),
        Some("*CONTROL_TERMINATION"),
        Some("ENDTIM"),
        "positive",
    );
}

#[test]
fn binary_and_non_utf8_input_is_an_error_not_a_panic() {
    let dir = std::env::temp_dir().join(format!("cleave-deck-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("bin.k");
    let mut bytes = BASE.as_bytes().to_vec();
    let at = BASE.find("5, 1., 1., 0.").unwrap() + 3;
    bytes[at] = 0xff;
    std::fs::write(&p, &bytes).unwrap();
    let e = cleave_io::deck::read_deck(&p).unwrap_err();
    assert_eq!(e.line, Some(line_of(BASE, "5, 1., 1., 0.")));
    assert_eq!(e.field.as_deref(), Some("X"));
    std::fs::write(&p, [0u8, 159, 146, 150, 0xff, 0xfe, b'\n', b'*', 0x80]).unwrap();
    assert!(cleave_io::deck::read_deck(&p).is_err());
    assert!(cleave_io::deck::read_deck(&dir.join("missing.k")).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------------
// robustness

/// xorshift64*: a small deterministic generator.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

#[test]
fn random_input_never_panics() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let alphabet = b"*$,.-+eEdD0123456789 \n\r\tKEYWORDNODEELMNT_SOLIDPARTabc\xff\x00";
    for _ in 0..300 {
        let n = rng.below(400);
        let bytes: Vec<u8> = (0..n)
            .map(|_| {
                if rng.below(4) == 0 {
                    rng.next() as u8
                } else {
                    alphabet[rng.below(alphabet.len())]
                }
            })
            .collect();
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_deck(&text, "r.k");
        let _ = parse_deck(&format!("*KEYWORD\n{text}"), "r.k");
    }
}

#[test]
fn mutated_decks_never_panic() {
    let mut rng = Rng(42);
    let fixed = to_fixed(BASE);
    for base in [BASE.to_string(), fixed] {
        let lines: Vec<&str> = base.lines().collect();
        for _ in 0..300 {
            let mut ls: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            for _ in 0..1 + rng.below(3) {
                let i = rng.below(ls.len());
                match rng.below(5) {
                    0 => {
                        let cut = rng.below(ls[i].len() + 1);
                        let mut s = ls[i].clone();
                        while !s.is_char_boundary(cut.min(s.len())) {
                            s.pop();
                        }
                        s.truncate(cut.min(s.len()));
                        ls[i] = s;
                    }
                    1 => {
                        ls.remove(i);
                    }
                    2 => {
                        let mut b: Vec<char> = ls[i].chars().collect();
                        if b.len() > 1 {
                            let (a, c) = (rng.below(b.len()), rng.below(b.len()));
                            b.swap(a, c);
                        }
                        ls[i] = b.into_iter().collect();
                    }
                    3 => {
                        let j = rng.below(ls.len());
                        let l = ls[j].clone();
                        ls.insert(i, l);
                    }
                    _ => {
                        let mut b: Vec<char> = ls[i].chars().collect();
                        if !b.is_empty() {
                            let a = rng.below(b.len());
                            b[a] = ['9', '-', ',', '.', 'x', ' ', '*', '0'][rng.below(8)];
                        }
                        ls[i] = b.into_iter().collect();
                    }
                }
            }
            let _ = parse_deck(&ls.join("\n"), "m.k");
        }
    }
}

// ---------------------------------------------------------------------------------------
// writer

fn rel_eq(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

fn round_trip_model() -> Model {
    let mesh = BoxMesh::new([3, 2, 2], [0.3, 0.07, 1.0 / 3.0]);
    let n = mesh.x.len();
    let ne = mesh.conn.len();
    let mut v0 = vec![[0.0; 3]; n];
    v0[5] = [1.5, -2.25e-3, 0.125]; // 10-character fields: ~7 digits
    Model {
        title: "round trip".into(),
        node_ids: (0..n as i64).map(|i| 100 + 3 * i).collect(),
        x0: mesh
            .x
            .iter()
            .map(|p| [p[0] - 0.1, p[1] * 1.0e-3, p[2] + 2.0])
            .collect(),
        v0: v0.into(),
        elem_ids: (0..ne as i64).map(|i| 7 + i).collect(),
        elem_part: (0..ne).map(|e| u32::from(e >= ne - 2)).collect(),
        conn: mesh.conn,
        parts: vec![
            Part {
                id: 10,
                title: "body".into(),
                section: 0,
                material: 1,
                hourglass: Some(0),
            },
            Part {
                id: 20,
                title: "".into(),
                section: 0,
                material: 0,
                hourglass: None,
            },
        ],
        sections: vec![Section { id: 3, elform: 1 }],
        materials: vec![
            Material {
                id: 5,
                density: 7850.0,
                young: 2.1e11,
                poisson: 0.3,
                kind: MaterialKind::Rigid {
                    cmo: 1,
                    con1: 7,
                    con2: 7,
                },
            },
            Material {
                id: 6,
                density: 2.7e3,
                young: 7.0e10,
                poisson: 0.33,
                kind: MaterialKind::PlasticKinematic {
                    sigy: 2.75e8,
                    etan: 6.0e8,
                    beta: 0.5,
                },
            },
            Material {
                id: 7,
                density: 7830.0,
                young: 2.0e11,
                poisson: 0.29,
                kind: MaterialKind::JohnsonCook(JohnsonCook::STEEL_4340),
            },
            Material {
                id: 8,
                density: 7830.0,
                young: 2.0e11,
                poisson: 0.29,
                kind: MaterialKind::JohnsonCook(JohnsonCook {
                    a: 7.92e8,
                    b: 5.1e8,
                    n: 0.26,
                    c: 0.0,
                    eps0: 1.0,
                    m: 1.0,
                    t_melt: f64::INFINITY,
                    t_room: 0.0,
                    rho_cp: f64::INFINITY,
                    sig_max: 1.5e9,
                    sig_sat: f64::INFINITY,
                    eos: None,
                }),
            },
            Material {
                id: 9,
                density: 7850.0,
                young: 2.1e11,
                poisson: 0.3,
                kind: MaterialKind::PiecewiseLinear(PiecewiseLinear {
                    points: vec![[0.0, 2.5e8], [0.05, 3.2e8], [0.5, 4.5e8]].into(),
                    c: 40.4,
                    p: 5.0,
                    lcss: None,
                    table: None,
                }),
            },
        ],
        curves: vec![cleave_core::curve::Curve {
            id: 9,
            t: vec![0.0, 1.0e-4, 1.0 / 3.0],
            y: vec![0.0, -12.345678901234, 2.0 / 3.0],
        }],
        node_sets: vec![NodeSet {
            id: 4,
            nodes: vec![0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10],
        }],
        part_sets: vec![PartSet {
            id: 2,
            parts: vec![1, 0],
        }],
        segment_sets: vec![SegmentSet {
            id: 8,
            segments: vec![[0, 1, 5, 4], [1, 2, 6, 6]],
        }],
        solid_sets: vec![SolidSet {
            id: 3,
            elems: vec![2, 0],
        }],
        nodal_rigid: vec![NodalRigidBody {
            id: 40,
            set: 0,
            cmo: 1,
            con1: 3,
            con2: 0,
            inertia: Some(GivenInertia {
                centre: [0.1, -0.25, 2.0],
                mass: 1.5,
                inertia: [[2.0, 0.5, 0.0], [0.5, 3.0, -0.25], [0.0, -0.25, 1.0]],
                velocity: [0.0, 1.0, 0.0],
                omega: [10.0, 0.0, -2.0],
            }),
        }],
        extra_nodes: vec![ExtraNodes {
            part: 1,
            set: None,
            nodes: vec![11],
            iflag: true,
        }],
        part_inertia: vec![PartInertia {
            part: 1,
            given: GivenInertia {
                centre: [0.05, 0.0, 2.1],
                mass: 25.0,
                inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]],
                velocity: [0.0, 0.0, -3.0],
                omega: [0.0; 3],
            },
        }],
        spcs: vec![
            Spc {
                node: 0,
                dof: [true, false, true, false, false, false],
            },
            Spc {
                node: 3,
                dof: [false, true, false, false, false, true],
            },
        ],
        prescribed: vec![
            PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(2),
                dof: MotionDof::Axis(1),
                vad: Vad::Displacement,
                curve: 0,
                sf: 2.5,
            },
            PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Rigid(1),
                dof: MotionDof::Axis(2),
                vad: Vad::Velocity,
                curve: 0,
                sf: -1.0,
            },
            PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(4),
                dof: MotionDof::Axis(0),
                vad: Vad::Velocity,
                curve: 0,
                sf: 1.0,
            },
            PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::NodalRigid(0),
                dof: MotionDof::Axis(1),
                vad: Vad::Velocity,
                curve: 0,
                sf: 2.0,
            },
        ],
        body_loads: vec![
            BodyLoad {
                axis: 2,
                curve: None,
                sf: 9.81,
            },
            BodyLoad {
                axis: 0,
                curve: Some(0),
                sf: 0.5,
            },
        ],
        node_loads: vec![NodeLoad {
            node: 3,
            axis: 1,
            curve: 0,
            sf: -250.0,
        }],
        pressure_loads: vec![PressureLoad {
            nodes: [0, 1, 5, 4],
            curve: 0,
            sf: 2.5e6,
            at: 1e-5,
        }],
        rigid_walls: vec![
            RigidWall {
                shape: cleave_core::model::WallShape::Plane,
                motion: None,
                extent: None,
                id: 1,
                nodes: None,
                tail: [0.0, 0.0, -0.5],
                head: [0.0, 0.0, 1.0],
                fric: 1.0,
            },
            RigidWall {
                shape: cleave_core::model::WallShape::Plane,
                motion: None,
                extent: None,
                id: 2,
                nodes: Some(vec![0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10]),
                tail: [0.0; 3],
                head: [1.0, 0.0, 0.0],
                fric: 0.0,
            },
            RigidWall {
                shape: cleave_core::model::WallShape::Plane,
                motion: None,
                extent: None,
                id: 3,
                nodes: Some(vec![3, 1]),
                tail: [0.0; 3],
                head: [0.0, 1.0, 0.0],
                fric: 0.25,
            },
        ],
        contacts: vec![
            ContactDef {
                id: 1,
                single_surface: true,
                one_way: false,
                slave: ContactSurface::All,
                master: None,
                fs: 0.3,
                fd: 0.2,
                dc: 1.0e-3,
            },
            ContactDef {
                id: 2,
                single_surface: false,
                one_way: false,
                slave: ContactSurface::PartSet(0),
                master: Some(ContactSurface::Part(1)),
                fs: 0.0,
                fd: 0.0,
                dc: 0.0,
            },
            ContactDef {
                id: 3,
                single_surface: false,
                one_way: false,
                slave: ContactSurface::SegmentSet(0),
                master: Some(ContactSurface::All),
                fs: 0.1,
                fd: 0.1,
                dc: 0.0,
            },
        ],
        hourglass: vec![HourglassDef {
            id: 12,
            hourglass: Hourglass::Stiffness,
            qh: 0.05,
            q1: 1.2,
            q2: 0.08,
        }],
        separations: vec![SeparationDef {
            material: 1,
            model: 3,
            sigmax: 3.0e8,
            beta: 0.7,
            gc: 1.2e4,
            bond: 0,
            strength: StrengthDist::Weibull {
                m: 6.5,
                aref: 2.5e-5,
                smin: 1.0e7,
                seed: 123_456_789,
            },
        }],
        tied: Vec::new(),
        erosion: vec![
            cleave_core::erosion::ErosionDef {
                material: 2,
                rule: cleave_core::erosion::ErosionRule {
                    max_principal: Some(1.5e9),
                    failure_time: Some(2.0e-4),
                    // 4340 steel (Johnson and Cook 1985)
                    johnson_cook: Some(cleave_core::erosion::JcDamage {
                        d: [0.05, 3.44, -2.12, 0.002, 0.61],
                        efmin: 1.0e-6,
                    }),
                    ncs: 2,
                    ..Default::default()
                },
            },
            cleave_core::erosion::ErosionDef {
                material: 4,
                rule: cleave_core::erosion::ErosionRule {
                    plastic_strain: Some(0.35),
                    min_pressure: Some(-1.0e9),
                    max_principal_strain: Some(0.3),
                    volumetric_strain: Some(-0.2),
                    ncs: 2,
                    ..Default::default()
                },
            },
        ],
        control: Control {
            end_time: 2.5e-4,
            dt_init: 1.0e-8,
            tssfac: 0.67,
            hourglass: Hourglass::Stiffness,
            qh: 0.05,
            q1: 1.0,
            q2: 0.1,
            slsfac: 0.15,
            penalty: PenaltyRule::Face,
            dt_min: 0.05,
            dt_max_curve: None,
        },
        output: OutputRequests {
            glstat_dt: 1.0e-6,
            nodout_dt: 2.0e-6,
            elout_dt: 3.0e-6,
            rwforc_dt: 4.0e-6,
            rcforc_dt: 5.0e-6,
            d3plot_dt: 1.0e-5,
            history_nodes: vec![3, 0],
            history_solids: vec![1],
        },
    }
}

/// `*MAT_JOHNSON_COOK` and `*MAT_SIMPLIFIED_JOHNSON_COOK`: the parameters as read, the
/// elastic constants of 015 from G and PR (or E), the defaults (M 1, no caps, no heating
/// without CP), and an error naming the field for each feature cleave does not model.
#[test]
fn johnson_cook_cards_are_read() {
    let mat = |text: &str| with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3", text);
    let jc015 = "*MAT_JOHNSON_COOK\n1, 7830., 7.7e10, , 0.29\n7.92e8, 5.1e8, 0.26, 0.014, 1.03, 1793., 294., 1.\n477.";
    let m = parse(&mat(jc015));
    let got = &m.materials[0];
    assert!(close(got.young, 2.0 * 7.7e10 * 1.29) && got.poisson == 0.29);
    let MaterialKind::JohnsonCook(jc) = got.kind else {
        panic!("{:?}", got.kind)
    };
    assert_eq!(
        jc,
        JohnsonCook {
            rho_cp: jc.rho_cp,
            ..JohnsonCook::STEEL_4340
        }
    );
    assert!(close(jc.rho_cp, 7830.0 * 477.0));
    assert_eq!((jc.sig_max, jc.sig_sat), (f64::INFINITY, f64::INFINITY));
    // E instead of PR
    let m = parse(&mat(&jc015.replace("7.7e10, , 0.29", "7.7e10, 1.986e11")));
    assert!((m.materials[0].poisson - (1.986e11 / 1.54e11 - 1.0)).abs() < 1e-12);
    let jc098 = "*MAT_SIMPLIFIED_JOHNSON_COOK\n1, 7830., 2.0e11, 0.29\n7.92e8, 5.1e8, 0.26, 0.014, , 1.5e9, , 1.";
    let m = parse(&mat(jc098));
    let MaterialKind::JohnsonCook(jc) = m.materials[0].kind else {
        panic!()
    };
    assert_eq!(
        (jc.sig_max, jc.sig_sat, jc.t_melt),
        (1.5e9, f64::INFINITY, f64::INFINITY)
    );
    assert_eq!((jc.m, jc.rho_cp), (1.0, f64::INFINITY));
    for (text, field, msg) in [
        (
            jc015.replace("7.7e10, , 0.29", "7.7e10"),
            "PR",
            "no part gives it an *EOS",
        ),
        (
            jc015.replace("7.7e10, , 0.29", "7.7e10, 2.5e11, 0.29"),
            "E",
            "disagrees",
        ),
        (jc015.replace(", 0.29", ", 0.29, , 2"), "VP", "0..1"),
        (
            jc015.replace(", 0.29", ", 0.29, , , 2"),
            "RATEOP",
            "rate form",
        ),
        (
            jc015.replace("1793., 294.", "200., 294."),
            "TM",
            "exceed TR",
        ),
        (
            jc015.replace("0.014, 1.03, 1793., 294., 1.", "0.014, 1.03, 1793., 294."),
            "EPSO",
            "positive",
        ),
        (jc015.replace("\n477.", "\n477., -1.0e9"), "PC", "spall"),
        (format!("{jc015}\n0., , 2"), "EROD", "not one of 0..1"),
        (
            format!("{jc015}\n0., , , -1."),
            "EFMIN",
            "must not be negative",
        ),
        (
            jc098.replace("0.014, , 1.5e9", "0.014, -0.8, 1.5e9"),
            "PSFAIL",
            "must not be negative",
        ),
        (
            jc098.replace("0.26, 0.014", "0., 0.014"),
            "N",
            "positive when B",
        ),
        (jc098.replace("7.92e8, 5.1e8", "0., 5.1e8"), "A", "positive"),
    ] {
        let e = err(&mat(&text));
        assert_eq!(e.field.as_deref(), Some(field), "{text}: {e}");
        assert!(e.to_string().contains(msg), "{text}: {e}");
    }
}

/// `*MAT_024` with LCSS a table of hardening curves by strain rate: `*DEFINE_TABLE` (its
/// curves the ones that follow it, values scaled by SFA and offset by OFFA) and
/// `*DEFINE_TABLE_2D` (curves named) read to the same table; a first value below 0 makes it a
/// table of log rates; the deck writer's table reads back to the same model; errors name
/// the card.
#[test]
fn piecewise_linear_plasticity_takes_a_rate_table() {
    let mat = |text: &str| with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3", text);
    let table = |m: &Model| match &m.materials[0].kind {
        MaterialKind::PiecewiseLinear(p) => p.clone(),
        k => panic!("{k:?}"),
    };
    let curves =
        "*DEFINE_CURVE\n21\n0., 2.5e8\n0.1, 3.0e8\n*DEFINE_CURVE\n22\n0., 3.5e8\n0.1, 4.5e8\n";
    let m024 = "*MAT_024\n1, 7800., 2.0e11, 0.3\n0., 0., 30\n";
    let plain = parse(&mat(&format!(
        "*DEFINE_TABLE\n30, 10., 1.\n0.1\n99.9\n{curves}{m024}"
    )));
    let p = table(&plain);
    let t = p.table.clone().expect("a table");
    assert_eq!((t.values.clone(), t.log), (vec![2.0, 1000.0], false));
    assert_eq!(t.curves[1].0, 22);
    assert_eq!(&*t.curves[1].1, &[[0.0, 3.5e8], [0.1, 4.5e8]]);
    assert_eq!(p.points, t.curves[0].1);
    let two_d = parse(&mat(&format!(
        "{curves}*DEFINE_TABLE_2D\n30, 10., 1.\n0.1, 21\n99.9, 22\n{m024}"
    )));
    assert_eq!(table(&two_d), p);
    let log = parse(&mat(&format!(
        "*DEFINE_TABLE_2D\n30\n-2.0, 21\n3.0, 22\n{curves}{m024}"
    )));
    assert!(table(&log).table.unwrap().log);
    // written and read back
    let back = parse(&write_deck(&plain));
    assert_eq!(table(&back), p);
    for (t, want) in [
        (
            format!("*DEFINE_TABLE\n30\n0.1\n99.9\n{}{m024}", &curves[..curves.find("*DEFINE_CURVE\n22").unwrap()]),
            "*DEFINE_TABLE 30 (line 33) has 2 values, so the 2 keywords after it must be its *DEFINE_CURVEs; 1 found here",
        ),
        (
            format!("*DEFINE_TABLE\n30\n5.\n1.\n{curves}{m024}"),
            "value 1 is not greater than the previous one (5)",
        ),
        (
            format!("*DEFINE_TABLE_2D\n21\n0.1, 21\n99.9, 22\n{curves}{m024}"),
            "table 21 has the id of the curve",
        ),
        (
            format!("*DEFINE_TABLE_2D\n30\n0.1, 21\n99.9, 22\n{curves}*MAT_024\n1, 7800., 2.0e11, 0.3\n40., 5., 30\n"),
            "the rate effect of a table LCSS (30) is in its curves",
        ),
        (
            format!("*DEFINE_TABLE_2D\n30\n0.1, 21\n99.9, 23\n{curves}{m024}"),
            "curve 23 is not defined",
        ),
    ] {
        let e = err(&mat(&t));
        assert!(e.to_string().contains(want), "want '{want}' in: {e}");
        assert!(e.line.is_some(), "{e}");
    }
}

/// `*MAT_PIECEWISE_LINEAR_PLASTICITY`: the hardening curve from LCSS (a `*DEFINE_CURVE`,
/// scaled), from EPS/ES, or from SIGY and ETAN, Cowper-Symonds C and P; errors name the field.
#[test]
fn piecewise_linear_plasticity_is_read() {
    let mat = |text: &str| with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3", text);
    let kind = |t: &str| match parse(&mat(t)).materials[0].kind.clone() {
        MaterialKind::PiecewiseLinear(p) => p,
        k => panic!("{k:?}"),
    };
    let curve =
        "*DEFINE_CURVE\n7, 0, 1., 1.0e6\n0., 250.\n0.1, 300.\n*MAT_PIECEWISE_LINEAR_PLASTICITY";
    let p = kind(&format!(
        "{curve}\n1, 7800., 2.0e11, 0.3, 1.0e8\n40.4, 5., 7"
    ));
    assert_eq!(&*p.points, &[[0.0, 250e6], [0.1, 300e6]]);
    assert_eq!((p.c, p.p, p.lcss), (40.4, 5.0, Some(7)));
    let p = kind("*MAT_024\n1, 7800., 2.0e11, 0.3\n\n0., 0.05, 0.5\n2.5e8, 3.2e8, 4.5e8");
    assert_eq!(&*p.points, &[[0.0, 2.5e8], [0.05, 3.2e8], [0.5, 4.5e8]]);
    assert_eq!((p.c, p.lcss), (0.0, None));
    let p = kind("*MAT_024\n1, 7800., 2.0e11, 0.3, 4.0e8, 2.0e9");
    assert_eq!(p.points[0], [0.0, 4.0e8]);
    assert!((p.points[1][1] - 4.0e8 - 2.0e11 * 2.0e9 / (2.0e11 - 2.0e9)).abs() < 1e-3);
    for (t, field, msg) in [
        ("*MAT_024\n1, 7800., 2.0e11, 0.3", "SIGY", "positive"),
        (
            "*MAT_024\n1, 7800., 2.0e11, 0.3, 4.0e8, , -1.0",
            "FAIL",
            "user failure subroutine",
        ),
        (
            "*MAT_024\n1, 7800., 2.0e11, 0.3, 4.0e8\n40.4",
            "P",
            "positive",
        ),
        (
            "*MAT_024\n1, 7800., 2.0e11, 0.3, 4.0e8\n, , , 3",
            "LCSR",
            "rate factor",
        ),
        (
            "*MAT_024\n1, 7800., 2.0e11, 0.3, 4.0e8\n, , 99",
            "LCSS",
            "curve or table 99 is not defined",
        ),
        (
            &format!(
                "{}\n1, 7800., 2.0e11, 0.3\n, , 7",
                curve.replace("0., 250.", "0.01, 250.")
            ),
            "LCSS",
            "start at 0",
        ),
    ] {
        let e = err(&mat(t));
        assert_eq!(e.field.as_deref(), Some(field), "{t}: {e}");
        assert!(e.to_string().contains(msg), "{t}: {e}");
    }
    // a field that is no number is an error even past the last point
    let e = err(&mat(
        "*MAT_024\n1, 7800., 2.0e11, 0.3\n\n0., 0.05\n2.5e8, 3.2e8, , , , , , x",
    ));
    assert_eq!(e.field.as_deref(), Some("ES8"), "{e}");
    // EPS/ES points out of order: the message says so, at the material's line
    let t = mat("*MAT_024\n1, 7800., 2.0e11, 0.3\n\n0., 0.1, 0.05\n2.5e8, 3.0e8, 3.2e8");
    let e = err(&t);
    assert!(e.to_string().contains("must increase"), "{e}");
    assert_eq!(e.line, Some(line_of(&t, "*MAT_024") + 1));
}

/// `*MAT_ADD_SEPARATION` with a strength distribution: DIST and SEED on card 1, card 2
/// `SMIN SMAX M AREF`; MODEL 4 (exponential law) needs GC.
#[test]
fn separation_strength_distributions_are_read() {
    let m = parse(&with(
        "1, 2, 1.0e8, 0.5",
        "1, 4, , 0.5, 40., , 1, 99\n1.0e8, 3.0e8",
    ));
    assert_eq!(
        m.separations[0],
        SeparationDef {
            material: 0,
            model: 4,
            sigmax: 0.0,
            beta: 0.5,
            gc: 40.0,
            bond: 1,
            strength: StrengthDist::Uniform {
                smin: 1.0e8,
                smax: 3.0e8,
                seed: 99,
            },
        }
    );
    let m = parse(&with(
        "1, 2, 1.0e8, 0.5",
        "1, 1, 2.0e8, , , , 2\n5.0e7, , 8., 1.0e-6",
    ));
    assert_eq!(
        m.separations[0].strength,
        StrengthDist::Weibull {
            m: 8.0,
            aref: 1.0e-6,
            smin: 5.0e7,
            seed: 0,
        }
    );
}

#[test]
fn write_then_read_round_trips() {
    let m = round_trip_model();
    let text = write_deck(&m);
    let back = match parse_deck(&text, "w.k") {
        Ok(d) => {
            assert!(d.warnings.is_empty(), "{:?}", d.warnings);
            d.model
        }
        Err(e) => panic!("{e}\n{text}"),
    };
    // the wall with nodes [3, 1] needs a set of its own
    assert_eq!(back.node_sets.len(), 2);
    assert_eq!(back.node_sets[1].nodes, vec![3, 1]);
    let mut back = back;
    back.node_sets.truncate(1);
    // floats to 1e-9, everything else exactly: compare the Debug text with floats rounded
    assert_eq!(m.x0.len(), back.x0.len());
    for (a, b) in m.x0.iter().flatten().zip(back.x0.iter().flatten()) {
        assert!(rel_eq(*a, *b), "{a} {b}");
    }
    for (a, b) in m.v0.iter().flatten().zip(back.v0.iter().flatten()) {
        assert!(rel_eq(*a, *b), "{a} {b}");
    }
    for (a, b) in m.curves[0]
        .t
        .iter()
        .chain(&m.curves[0].y)
        .zip(back.curves[0].t.iter().chain(&back.curves[0].y))
    {
        assert!(rel_eq(*a, *b), "{a} {b}");
    }
    let strip = |mut m: Model| {
        m.x0.clear();
        m.v0.clear();
        m.curves.iter_mut().for_each(|c| {
            c.t.clear();
            c.y.clear();
        });
        format!("{m:?}")
    };
    assert_eq!(strip(back), strip(m));
    // and the fixed-format deck has no commas
    assert!(
        !text.lines().any(|l| !l.starts_with('$') && l.contains(',')),
        "{text}"
    );
}

#[test]
fn writer_falls_back_to_free_format_for_wide_ids() {
    let mut m = round_trip_model();
    m.node_ids[0] = 1_234_567_890;
    let text = write_deck(&m);
    assert!(text.lines().any(|l| l.starts_with("1234567890,")));
    let back = parse_deck(&text, "w.k").unwrap().model;
    assert_eq!(back.node_ids[0], 1_234_567_890);
}

#[test]
fn text_beyond_the_card_is_an_error() {
    let f = to_fixed(BASE);
    let node = format!("{:>8}{:>16}{:>16}{:>16}", 5, "1.", "1.", "0.");
    assert!(f.contains(&node));
    let t = f.replacen(&node, &format!("{node}{:>8}{:>8}{:>8}", 0, 0, 9), 1);
    let e = err(&t);
    assert_eq!(e.line, Some(line_of(&t, &node)));
    assert!(e.message.contains("beyond column 72"), "{e}");
}

#[test]
#[ignore]
fn large_deck_timing() {
    let mesh = BoxMesh::new([60, 60, 30], [1.0, 1.0, 0.5]);
    let mut m = round_trip_model();
    m.x0 = mesh.x.into();
    m.v0 = vec![[0.0; 3]; m.x0.len()].into();
    m.node_ids = (1..=m.x0.len() as i64).collect();
    m.elem_ids = (1..=mesh.conn.len() as i64).collect();
    m.elem_part = vec![0; mesh.conn.len()];
    m.conn = mesh.conn;
    let t0 = std::time::Instant::now();
    let text = write_deck(&m);
    let t1 = std::time::Instant::now();
    let d = parse_deck(&text, "big.k").unwrap();
    let t2 = std::time::Instant::now();
    println!(
        "{} elements, {} MB: write {:?}, read {:?}",
        d.model.num_elements(),
        text.len() / 1_000_000,
        t1 - t0,
        t2 - t1
    );
}

/// A fresh directory for one test's files.
fn tmp_dir(name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// BASE split over three files: the nodes in `mesh/nodes.k` (included from beside the deck,
/// ending in its own `*END`), the elements in `lib/elems.k` found through `*INCLUDE_PATH`, a
/// long name continued with ` +`. The model is the one-file deck's, every field.
#[test]
fn include_reads_split_decks_as_one() {
    let d = tmp_dir("include-split");
    let (head, rest) = BASE.split_once("*NODE\n").unwrap();
    let (nodes, rest) = rest.split_once("*ELEMENT_SOLID\n").unwrap();
    let (elems, tail) = rest.split_once("*SET_NODE_LIST\n").unwrap();
    std::fs::create_dir_all(d.join("mesh")).unwrap();
    std::fs::create_dir_all(d.join("lib")).unwrap();
    std::fs::write(
        d.join("mesh/nodes.k"),
        format!("*KEYWORD\n$ nodes\n*NODE\n{nodes}*END\n*JUNK\n"),
    )
    .unwrap();
    std::fs::write(d.join("lib/elems.k"), format!("*ELEMENT_SOLID\n{elems}")).unwrap();
    let main = format!(
        "{head}*INCLUDE_PATH\nlib\n*INCLUDE\nmesh/no +\ndes.k\nelems.k\n*SET_NODE_LIST\n{tail}"
    );
    let path = d.join("main.k");
    std::fs::write(&path, &main).unwrap();
    let split = cleave_io::deck::read_deck(&path).unwrap();
    assert!(split.warnings.is_empty(), "{:?}", split.warnings);
    assert_eq!(format!("{:?}", split.model), format!("{:?}", parse(BASE)));
}

/// Errors in and around included files name the file and line where the card is: a bad
/// field in an included file, an id defined in two files (both named), a missing file (the
/// places searched), a file including itself (the chain), and the variants cleave does not
/// apply.
#[test]
fn include_errors_name_the_file() {
    let d = tmp_dir("include-errors");
    let (head, rest) = BASE.split_once("*NODE\n").unwrap();
    let (nodes, tail) = rest.split_once("*ELEMENT_SOLID\n").unwrap();
    let main = format!("{head}*INCLUDE\nnodes.k\n*ELEMENT_SOLID\n{tail}");
    let path = d.join("main.k");
    std::fs::write(&path, &main).unwrap();
    let inc = d.join("nodes.k");
    let inc_name = inc.display().to_string();
    let read = || cleave_io::deck::read_deck(&path).unwrap_err();

    std::fs::write(
        &inc,
        format!("*NODE\n{}", nodes.replace("5, 1., 1., 0.", "5, 1., x, 0.")),
    )
    .unwrap();
    let e = read();
    assert_eq!(
        (e.file.as_str(), e.line, e.field.as_deref()),
        (inc_name.as_str(), Some(6), Some("Y")),
        "{e}"
    );

    std::fs::write(&inc, format!("*NODE\n{nodes}*NODE\n12, 5., 5., 5.\n")).unwrap();
    let e = read();
    assert_eq!(e.file, inc_name, "{e}");
    assert!(
        e.message
            .contains("node 12 is defined twice (first at line 13)"),
        "{e}"
    );
    std::fs::write(&inc, format!("*NODE\n{nodes}")).unwrap();
    let twice = format!("{head}*NODE\n12, 5., 5., 5.\n*INCLUDE\nnodes.k\n*ELEMENT_SOLID\n{tail}");
    std::fs::write(&path, &twice).unwrap();
    let e = read();
    assert_eq!(e.file, inc_name, "{e}");
    assert!(
        e.message.contains(&format!("first at {}:", path.display())),
        "{e}"
    );

    std::fs::write(&path, &main).unwrap();
    std::fs::remove_file(&inc).unwrap();
    let e = read();
    let line = main.lines().position(|l| l == "nodes.k").unwrap() + 1;
    assert_eq!(
        (e.file.as_str(), e.line),
        (path.to_str().unwrap(), Some(line)),
        "{e}"
    );
    assert!(
        e.message.contains("cannot find 'nodes.k' (looked in:"),
        "{e}"
    );

    std::fs::write(&inc, "*INCLUDE\nmain.k\n").unwrap();
    let e = read();
    assert!(e.message.contains("includes itself"), "{e}");

    std::fs::write(&inc, "*INCLUDE_TRANSFORM\nx.k\n").unwrap();
    let e = read();
    assert_eq!(
        (e.file.as_str(), e.keyword.as_deref()),
        (inc_name.as_str(), Some("*INCLUDE_TRANSFORM")),
        "{e}"
    );
}

/// Cards ANSYS Workbench and LS-PrePost write that change nothing in a structural run of solids
/// are read past with a warning: `*CONTROL_SOLUTION` SOLN 0, `*CONTROL_SHELL` (a
/// `*DEFINE_COORDINATE_SYSTEM` is read: tests/frames.rs);
/// `*PARAMETER_DUPLICATION` DFLAG says which of two definitions of a name holds (without it
/// a name defined twice stays an error). SOLN 1 (thermal) is an error naming the field.
#[test]
fn workbench_cards_that_change_nothing_are_read_past() {
    let extra = "*CONTROL_SOLUTION\n0, 0, 0\n*CONTROL_SHELL\n20., 0, -1, 0, 2, 2, 1, 1\n\
                 *DEFINE_COORDINATE_SYSTEM\n7, 0., 0., 0., 1., 0., 0.\n0., 1., 0.\n";
    let d = parse_deck(&with("*END", &format!("{extra}*END")), "t.k").unwrap();
    assert_eq!(d.model.materials, parse(BASE).materials);
    for k in ["*CONTROL_SOLUTION", "*CONTROL_SHELL"] {
        assert!(
            d.warnings.iter().any(|w| w.contains(k)),
            "{k}: {:?}",
            d.warnings
        );
    }
    let e = err(&with("*END", "*CONTROL_SOLUTION\n1\n*END"));
    assert_eq!(e.field.as_deref(), Some("SOLN"), "{e}");
    // a parameter defined twice: an error, or the first or last as DFLAG says
    let twice = "*PARAMETER\nR rho, 1000.\n*PARAMETER\nR rho, 7800.\n";
    let deck = |dflag: &str| {
        with(
            "*MAT_ELASTIC\n1, 7800.",
            &format!("{twice}{dflag}*MAT_ELASTIC\n1, &rho"),
        )
    };
    assert!(err(&deck("")).message.contains("defined twice"));
    assert_eq!(
        parse(&deck("*PARAMETER_DUPLICATION\n1\n")).materials[0].density,
        1000.0
    );
    assert_eq!(
        parse(&deck("*PARAMETER_DUPLICATION\n4\n")).materials[0].density,
        7800.0
    );
    let e = err(&deck("*PARAMETER_DUPLICATION\n5\n"));
    assert_eq!(e.field.as_deref(), Some("DFLAG"), "{e}");
}

/// `*PARAMETER` and `*PARAMETER_EXPRESSION`: BASE with some of its numbers replaced by
/// `&name` references (reals, an integer id, a negated value, an expression, defined after
/// their use and in fixed as well as free format) reads as BASE; an undefined name is an
/// error at its line naming the field's position.
#[test]
fn parameters_stand_for_their_values() {
    let t = with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3", "*MAT_ELASTIC\n&mid, &rho, &e, &nu")
        .replacen("1.0e-3, 1.", "&tend, -&neg", 1)
        .replacen(
            "*END",
            "*PARAMETER\nI mid      1         R rho      7800.\n*PARAMETER\nR nu, 0.3, R neg, -1.\n*PARAMETER_EXPRESSION\nR e        2.0e11 * nu / 0.3\nR tend, max(1.0e-3, 0.5e-3)\n*END",
            1,
        );
    assert_eq!(format!("{:?}", parse(&t)), format!("{:?}", parse(BASE)));
    let bad = t.replacen("&rho,", "&rhoo,", 1);
    let e = err(&bad);
    assert_eq!(e.line, Some(line_of(&bad, "&mid, &rhoo")), "{e}");
    assert!(
        e.message
            .contains("field 2: parameter &rhoo is not defined"),
        "{e}"
    );
}

/// `*CONTROL_` cards that change nothing cleave computes (energy and output switches, CPU and
/// parallel options) are read past, each with one warning naming file, line and keyword;
/// one that changes the physics stays an error.
#[test]
fn control_cards_that_change_nothing_warn() {
    let t = with(
        "*CONTROL_CONTACT",
        "*CONTROL_ENERGY\n2, 2, 2, 2\n*CONTROL_OUTPUT\n1\n*CONTROL_MPP_IO_NOD3DUMP\n*CONTROL_CONTACT",
    );
    let d = parse_deck(&t, "t.k").unwrap();
    assert_eq!(d.warnings.len(), 3, "{:?}", d.warnings);
    assert!(d.warnings[0].starts_with(&format!(
        "t.k:{}: *CONTROL_ENERGY",
        line_of(&t, "*CONTROL_ENERGY")
    )));
    assert_eq!(format!("{:?}", d.model), format!("{:?}", parse(BASE)));
    let t = with(
        "*CONTROL_CONTACT",
        "*CONTROL_DYNAMIC_RELAXATION\n\n*CONTROL_CONTACT",
    );
    assert!(err(&t).to_string().contains("not supported"));
}

/// `*SET_NODE_LIST_GENERATE` and `*SET_PART_LIST_GENERATE`: ranges of ids, the defined ones
/// members; the test deck with its two sets written as ranges reads to the same model. A
/// range that holds no id, or runs backwards, is an error at its line.
#[test]
fn generated_sets_take_the_ids_in_their_ranges() {
    let t = with(
        "*SET_NODE_LIST\n1\n1, 4, 7, 10, 0, 1",
        "*SET_NODE_LIST_GENERATE\n1\n1, 1, 4, 4, 7, 7, 10, 10",
    )
    .replacen(
        "*SET_PART_LIST\n5\n1, 2",
        "*SET_PART_LIST_GENERATE\n5\n1, 2",
        1,
    );
    assert_eq!(format!("{:?}", parse(&t)), format!("{:?}", parse(BASE)));
    // gaps in the numbering are skipped: nodes 2..=6 of the twelve
    let t2 = t.replacen("1, 1, 4, 4, 7, 7, 10, 10", "2, 6", 1);
    assert_eq!(parse(&t2).node_sets[0].nodes, vec![1, 2, 3, 4, 5]);
    let bad = t.replacen("1, 1, 4, 4, 7, 7, 10, 10", "100, 200", 1);
    let e = err(&bad);
    assert_eq!(e.line, Some(line_of(&bad, "100, 200")), "{e}");
    assert!(
        e.message.contains("no node has an id from 100 to 200"),
        "{e}"
    );
    let e = err(&t.replacen("1, 1, 4, 4, 7, 7, 10, 10", "6, 2", 1));
    assert_eq!(e.field.as_deref(), Some("B1END"), "{e}");
}

/// `*INITIAL_VELOCITY`: a node set's nodes (or every node, NSID blank) take the velocity,
/// cards applied in deck order after the test deck's own; a box or an undefined set is an
/// error naming the field.
#[test]
fn initial_velocity_of_a_set_or_of_all() {
    let base = parse(BASE);
    let t = with(
        "*END",
        "*INITIAL_VELOCITY\n1\n0.5, -2., 3., 0., 0., 0.\n*END",
    );
    let m = parse(&t);
    let set: Vec<u32> = m.node_sets[0].nodes.clone();
    for i in 0..m.num_nodes() {
        let expect = if set.contains(&(i as u32)) {
            [0.5, -2.0, 3.0]
        } else {
            base.v0[i]
        };
        assert_eq!(m.v0[i], expect, "node {i}");
    }
    let m = parse(&with("*END", "*INITIAL_VELOCITY\n\n0., 0., -7.\n*END"));
    assert!((0..m.num_nodes()).all(|i| m.v0[i] == [0.0, 0.0, -7.0]));
    let e = err(&with(
        "*END",
        "*INITIAL_VELOCITY\n1, , 4\n0., 0., -7.\n*END",
    ));
    assert_eq!(e.field.as_deref(), Some("BOXID"), "{e}");
    let e = err(&with("*END", "*INITIAL_VELOCITY\n9\n0., 0., -7.\n*END"));
    assert_eq!(e.field.as_deref(), Some("NSID"), "{e}");
    assert!(e.message.contains("node set 9 is not defined"), "{e}");
}

/// ELFORM 10 and 13 take tetrahedra only; a hexahedron in such a part is an error naming
/// element, shape and part at the element's line.
#[test]
fn tetrahedron_formulations_refuse_hexahedra() {
    for form in ["10", "13"] {
        let t = with(
            "*SECTION_SOLID\n1, 1",
            &format!("*SECTION_SOLID\n1, {form}"),
        );
        let e = err(&t);
        assert_eq!(e.keyword.as_deref(), Some("*ELEMENT_SOLID"), "{e}");
        assert!(
            e.message.contains(&format!(
                "element 1 is a hexahedron in part 1, whose section has ELFORM {form}"
            )),
            "{e}"
        );
    }
}

/// `*MAT_JOHNSON_COOK` with PR blank and a Mie-Gruneisen `*EOS_GRUNEISEN` on its part: the
/// material carries the EOS with rho0 = RO, and its elastic constants come from G and
/// K0 = rho0 C^2 (E = 9 K0 G / (3 K0 + G)); written and read back it is the same model. Errors:
/// an undefined EOSID, an EOS on an elastic material, PR blank without an EOS, two parts giving
/// one material different EOS.
#[test]
fn johnson_cook_takes_an_equation_of_state_from_its_part() {
    use cleave_core::material::Eos;
    let jc = "*MAT_JOHNSON_COOK\n1, 7830., 8.18e10\n7.92e8, 5.1e8, 0.26, 0.014, 1.03, 1793., 294., 1.0\n477.\n*EOS_GRUNEISEN\n5, 4578., 1.33, 0., 0., 1.67, 0.43\n1.0\n";
    let t =
        with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n", jc).replacen("1, 1, 1\n", "1, 1, 1, 5\n", 1);
    let m = parse(&t);
    let mat = &m.materials[0];
    let MaterialKind::JohnsonCook(j) = mat.kind else {
        panic!("a Johnson-Cook material")
    };
    let Some(Eos::Gruneisen {
        c, rho0, gamma0, a, ..
    }) = j.eos
    else {
        panic!("the EOS is attached: {:?}", j.eos)
    };
    assert_eq!((c, rho0, gamma0, a), (4578.0, 7830.0, 1.67, 0.43));
    let (k0, g) = (7830.0 * 4578.0f64 * 4578.0, 8.18e10);
    assert!(close(mat.young, 9.0 * k0 * g / (3.0 * k0 + g)));
    assert!(close(mat.shear_modulus(), g));
    assert!(close(mat.bulk_modulus(), k0));
    let again = parse(&write_deck(&m));
    assert_eq!(again.materials[0].kind, m.materials[0].kind);
    assert!(close(again.materials[0].young, mat.young));
    // errors
    let e = err(&t.replacen("1, 1, 1, 5\n", "1, 1, 1, 6\n", 1));
    assert!(
        e.message.contains("equation of state 6 is not defined"),
        "{e}"
    );
    assert_eq!(e.field.as_deref(), Some("EOSID"));
    let e = err(&t.replacen("2, 1, 2\n", "2, 1, 2, 5\n", 1));
    assert!(e.message.contains("*MAT_JOHNSON_COOK only"), "{e}");
    let e = err(&t.replacen("1, 1, 1, 5\n", "1, 1, 1\n", 1));
    assert!(e.message.contains("PR (or E) is missing"), "{e}");
    assert_eq!(e.field.as_deref(), Some("PR"));
}

/// What LS-PrePost and other people's decks write around the cards cleave reads: the `_ID`
/// (and `_TITLE`) options of boundary conditions and contacts (a first card `ID HEADING`),
/// `*SET_PART` for `*SET_PART_LIST`, read to the same model as BASE; `*CONTROL_ACCURACY`, the
/// `*CONTROL_IMPLICIT_` cards of an explicit run and `*CONTACT_FORCE_TRANSDUCER_PENALTY` warn;
/// an implicit run (IMFLAG 1) is an error naming the field.
#[test]
fn id_options_and_cards_of_other_decks() {
    let base = parse(BASE);
    let t = BASE
        .replacen("*BOUNDARY_SPC_SET\n", "*BOUNDARY_SPC_SET_ID\n1BC_y0\n", 1)
        .replacen(
            "*BOUNDARY_PRESCRIBED_MOTION_SET\n",
            "*BOUNDARY_PRESCRIBED_MOTION_SET_ID\n0MovingNodes\n",
            1,
        )
        .replacen(
            "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n",
            "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID\n         1Ball to Plate\n",
            1,
        )
        .replacen(
            "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n",
            "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TITLE\n2 plate\n",
            1,
        )
        .replacen("*SET_PART_LIST\n", "*SET_PART\n", 1)
        .replacen(
            "*END\n",
            "*CONTROL_ACCURACY\n1, 4, 0, 1\n*CONTROL_IMPLICIT_GENERAL\n0, 1.0\n*CONTROL_IMPLICIT_SOLVER\n6\n*CONTACT_FORCE_TRANSDUCER_PENALTY\n1, 2, 3, 3\n*END\n",
            1,
        );
    let d = parse_deck(&t, "t.k").unwrap_or_else(|e| panic!("{e}"));
    let m = &d.model;
    assert_eq!(m.spcs, base.spcs);
    assert_eq!(m.prescribed, base.prescribed);
    assert_eq!(m.contacts, base.contacts);
    assert_eq!(m.part_sets, base.part_sets);
    for k in [
        "*CONTROL_ACCURACY",
        "*CONTROL_IMPLICIT_GENERAL",
        "*CONTROL_IMPLICIT_SOLVER",
        "*CONTACT_FORCE_TRANSDUCER_PENALTY",
    ] {
        assert!(
            d.warnings.iter().any(|w| w.contains(k)),
            "{k}: {:?}",
            d.warnings
        );
    }
    let implicit = t.replacen(
        "*CONTROL_IMPLICIT_GENERAL\n0, 1.0",
        "*CONTROL_IMPLICIT_GENERAL\n1, 1.0",
        1,
    );
    let e = err(&implicit);
    assert_eq!(e.field.as_deref(), Some("IMFLAG"), "{e}");
    assert!(
        e.message.contains("implicit analysis is not supported"),
        "{e}"
    );
}

/// A value wider than its fixed-format field (as `     1.0E-3` in the first 10 columns,
/// seen in a public deck) is an error that says the text runs across the field's edge and
/// how wide the fields are.
#[test]
fn a_value_across_a_field_edge_is_explained() {
    let t = with(
        "*CONTROL_TERMINATION\n",
        "*CONTROL_TERMINATION\n     1.0E-3\n$",
    );
    let e = err(&t);
    assert_eq!(e.field.as_deref(), Some("ENDTIM"), "{e}");
    assert!(e.message.contains("'1.0E-' is not a number"), "{e}");
    assert!(
        e.message
            .contains("runs across the edge of this field (columns 1-10)"),
        "{e}"
    );
    // a field cleave reads only to warn about is still a number: ENDTIM pushed 3 columns
    // right reads as 1.0 and leaves 'e-6' to ENDCYC, which must not pass as a warning
    let t = with(
        "*CONTROL_TERMINATION\n",
        "*CONTROL_TERMINATION\n       1.0e-6\n$",
    );
    let e = err(&t);
    assert_eq!(e.field.as_deref(), Some("ENDCYC"), "{e}");
    assert!(
        e.message.contains("'e-6' is not a number") && e.message.contains("(columns 11-20)"),
        "{e}"
    );
}

/// `*LOAD_NODE_POINT`, `*LOAD_NODE_SET` (expanded per node), `*LOAD_SEGMENT` (a triangle as
/// N1 N2 N3 N3) and `*LOAD_SEGMENT_SET`; written and read back the same; a moment (DOF 5), a
/// quadratic segment and repeated nodes are errors naming the field or the segment.
#[test]
fn nodal_and_pressure_loads_are_read() {
    let loads = "*LOAD_NODE_POINT\n12, 3, 2, 2.5\n*LOAD_NODE_SET\n1, 1, 2\n*LOAD_SEGMENT\n2, 5.0e6, 1.0e-4, 1, 2, 5, 4\n2, 1.0e6, 0., 3, 6, 9, 9\n*LOAD_SEGMENT_SET\n3, 2, 2.0, 0.\n*END\n";
    let t = BASE.replacen("*END\n", loads, 1);
    let m = parse(&t);
    // node 12 along z, then the 4 nodes of set 1 along x
    assert_eq!(m.node_loads.len(), 5);
    assert_eq!(m.node_loads[0].axis, 2);
    assert_eq!(m.node_ids[m.node_loads[0].node as usize], 12);
    assert!(close(m.node_loads[0].sf, 2.5));
    assert!(m.node_loads[1..].iter().all(|l| l.axis == 0 && l.sf == 1.0));
    // two segments, then the 2 of segment set 3
    assert_eq!(m.pressure_loads.len(), 4);
    let p0 = &m.pressure_loads[0];
    assert_eq!(p0.nodes.map(|n| m.node_ids[n as usize]), [1, 2, 5, 4]);
    assert!(close(p0.sf, 5e6) && close(p0.at, 1e-4));
    assert_eq!(m.pressure_loads[1].nodes[2], m.pressure_loads[1].nodes[3]);
    assert_eq!(m.pressure_loads[2].nodes, m.segment_sets[0].segments[0]);
    let again = parse(&write_deck(&m));
    assert_eq!(again.node_loads, m.node_loads);
    assert_eq!(again.pressure_loads, m.pressure_loads);
    // errors
    let e = err(&t.replacen("12, 3, 2, 2.5", "12, 5, 2, 2.5", 1));
    assert_eq!(e.field.as_deref(), Some("DOF"), "{e}");
    let e = err(&t.replacen("1, 2, 5, 4\n", "1, 2, 5, 4, 7\n", 1));
    assert_eq!(e.field.as_deref(), Some("N5"), "{e}");
    let e = err(&t.replacen("1, 2, 5, 4\n", "1, 2, 2, 4\n", 1));
    assert!(e.message.contains("repeated nodes"), "{e}");
}

/// `*CONSTRAINED_NODAL_RIGID_BODY` (plain and `_SPC_INERTIA`), `*CONSTRAINED_EXTRA_NODES_NODE`
/// / `_SET`, `*PART_INERTIA`, `*CONTROL_SOLID`, `*SET_SOLID` / `_GENERATE` and
/// `*DATABASE_HISTORY_SOLID_SET`: read into the model, written back and read to the same, and
/// an error naming keyword, line and field for each card cleave does not model.
#[test]
fn rigid_bodies_of_nodes_inertia_and_solid_sets_are_read() {
    let part_inertia = "*PART_INERTIA\nplate\n2, 1, 2\n1.5, 0.5, 0.5, 10.0, 0, 0\n2.0, -0.5, 0.0, 3.0, 0.0, 4.0\n1.0, 0.0, 0.0, 0.0, 0.0, 5.0";
    let extra = "\
*NODE
13, 5., 5., 5.
14, 6., 5., 5.
*SET_NODE_LIST
9
1, 4
*SET_NODE_LIST
10
7, 10
*SET_NODE_LIST
11
13
*CONSTRAINED_NODAL_RIGID_BODY
50, , 9
*CONSTRAINED_NODAL_RIGID_BODY_SPC_INERTIA
51, , 10
1, 7, 0
0.0, 0.5, 1.0, 2.5, 0
1.0, 0.0, 0.0, 1.0, 0.0, 1.0
0.0, 0.0, -1.0, 0.0, 3.0, 0.0
*CONSTRAINED_EXTRA_NODES_NODE
2, 14, 1
*CONSTRAINED_EXTRA_NODES_SET
2, 11
*BOUNDARY_PRESCRIBED_MOTION_RIGID
50, 1, 0, 1, 2.0
*CONTROL_SOLID
1, 0, 0, 0, 0, 0.5
*SET_SOLID
20
2, 1
*SET_SOLID_GENERATE_TITLE
all
21
1, 2
*DATABASE_HISTORY_SOLID_SET
20
*END
";
    let t = with("*PART\nplate\n2, 1, 2", part_inertia).replacen("*END\n", extra, 1);
    let d = parse_deck(&t, "t.k").unwrap_or_else(|e| panic!("{e}"));
    let m = d.model;
    let solid_warning = d
        .warnings
        .iter()
        .find(|w| w.contains("*CONTROL_SOLID"))
        .expect("a warning");
    assert!(solid_warning.contains("T10JTOL = 0.5"), "{solid_warning}");
    // the nodal rigid bodies: PID, node set, constraints, given inertia
    assert_eq!(m.nodal_rigid.len(), 2);
    let (b0, b1) = (&m.nodal_rigid[0], &m.nodal_rigid[1]);
    assert_eq!((b0.id, m.node_sets[b0.set].id, b0.cmo), (50, 9, 0));
    assert!(b0.inertia.is_none());
    assert_eq!((b1.id, m.node_sets[b1.set].id), (51, 10));
    assert_eq!((b1.cmo, b1.con1, b1.con2), (1, 7, 0));
    let g = b1.inertia.as_ref().unwrap();
    assert_eq!((g.centre, g.mass), ([0.0, 0.5, 1.0], 2.5));
    assert_eq!(
        g.inertia,
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    );
    assert_eq!((g.velocity, g.omega), ([0.0, 0.0, -1.0], [0.0, 3.0, 0.0]));
    // extra nodes: node 14 with IFLAG 1, set 11 (node 13)
    assert_eq!(m.extra_nodes.len(), 2);
    assert_eq!(m.extra_nodes[0].part, 1);
    assert_eq!(m.node_ids[m.extra_nodes[0].nodes[0] as usize], 14);
    assert!(m.extra_nodes[0].iflag && m.extra_nodes[0].set.is_none());
    assert_eq!(m.extra_nodes[1].set.map(|s| m.node_sets[s].id), Some(11));
    assert!(!m.extra_nodes[1].iflag);
    // the part inertia, the tensor symmetric from its 6 components
    assert_eq!(m.part_inertia.len(), 1);
    let pi = &m.part_inertia[0];
    assert_eq!(
        (pi.part, pi.given.mass, pi.given.centre),
        (1, 10.0, [1.5, 0.5, 0.5])
    );
    assert_eq!(
        pi.given.inertia,
        [[2.0, -0.5, 0.0], [-0.5, 3.0, 0.0], [0.0, 0.0, 4.0]]
    );
    assert_eq!(
        (pi.given.velocity, pi.given.omega),
        ([1.0, 0.0, 0.0], [0.0, 0.0, 5.0])
    );
    // motion on the nodal rigid body by its PID
    assert_eq!(
        m.prescribed.last().unwrap().target,
        MotionTarget::NodalRigid(0)
    );
    // solid sets in their order, and the history set expanded after element 2
    assert_eq!(m.solid_sets.len(), 2);
    assert_eq!(m.solid_sets[0].elems, vec![1, 0]);
    assert_eq!(m.solid_sets[1].elems, vec![0, 1]);
    assert_eq!(m.output.history_solids, vec![1, 0]);
    // the bodies the solver builds: part 2 (given mass 10 plus node 14's; node 13's is not
    // added, IFLAG 0), the nodal bodies of nodes 1, 4 and 7, 10
    // (BASE prescribes the motion of node set 1, now in nodal rigid bodies: an error there)
    let e = cleave_core::setup::Setup::new(&m).unwrap_err();
    assert!(e.contains("prescribed motion on node 1"), "{e}");
    let mut free = m.clone();
    free.prescribed
        .retain(|p| !matches!(p.target, MotionTarget::Node(_)));
    let setup = cleave_core::setup::Setup::new(&free).unwrap();
    assert_eq!(setup.rigid.len(), 3);
    assert_eq!(setup.rigid[0].mass, 10.0); // nodes 13, 14 are of no element: massless
    assert_eq!(setup.rigid[0].nodes.len(), 8 + 2);
    assert_eq!(setup.rigid[2].mass, 2.5);
    // written and read back: the same
    let back = parse(&write_deck(&m));
    assert_eq!(back.nodal_rigid, m.nodal_rigid);
    assert_eq!(back.extra_nodes, m.extra_nodes);
    assert_eq!(back.part_inertia, m.part_inertia);
    assert_eq!(back.solid_sets, m.solid_sets);
    assert_eq!(back.prescribed, m.prescribed);
    assert_eq!(back.output.history_solids, m.output.history_solids);
    assert_eq!(back.node_sets, m.node_sets);

    // errors, each naming keyword, line and field
    let e = err(&t.replacen("50, , 9\n", "50, , 9, 0, 0, 1\n", 1));
    let kw = "*CONSTRAINED_NODAL_RIGID_BODY";
    check(
        &e,
        Some(line_of(&t, "50, , 9")),
        Some(kw),
        Some("DRFLAG"),
        "releasing",
    );
    let e = err(&t.replacen("50, , 9\n", "50, , 9, 4\n", 1));
    check(
        &e,
        Some(line_of(&t, "50, , 9")),
        Some(kw),
        Some("PNODE"),
        "centre of mass",
    );
    let e = err(&t.replacen("51, , 10\n", "51, 3, 10\n", 1));
    assert_eq!(e.field.as_deref(), Some("CID"), "{e}");
    let e = err(&t.replacen("50, , 9\n", "2, , 9\n", 1));
    check(
        &e,
        Some(line_of(&t, "50, , 9")),
        Some(kw),
        Some("PID"),
        "*PART's id",
    );
    let e = err(&t.replacen("0.0, 0.5, 1.0, 2.5, 0", "0.0, 0.5, 1.0, , 0", 1));
    assert_eq!(e.field.as_deref(), Some("TM"), "{e}");
    let e = err(&t.replacen(
        "1.0, 0.0, 0.0, 1.0, 0.0, 1.0",
        "1.0, 2.0, 0.0, 1.0, 0.0, 1.0",
        1,
    ));
    assert!(e.message.contains("positive definite"), "{e}");
    let e = err(&t.replacen(
        "*PART\nblock\n1, 1, 1",
        "*PART_INERTIA\nblock\n1, 1, 1\n0., 0., 0., 1.\n1., 0., 0., 1., 0., 1.\n0., 0., 0.\n",
        1,
    ));
    check(
        &e,
        Some(line_of(&t, "1, 1, 1")),
        Some("*PART_INERTIA"),
        Some("MID"),
        "rigid parts only",
    );
    let e = err(&t.replacen("2, 14, 1", "1, 14, 1", 1));
    check(
        &e,
        Some(line_of(&t, "2, 14, 1")),
        Some("*CONSTRAINED_EXTRA_NODES_NODE"),
        Some("PID"),
        "not rigid",
    );
    let e = err(&t.replacen("1, 0, 0, 0, 0, 0.5", "1, 0, 0, 0, 1", 1));
    check(
        &e,
        Some(line_of(&t, "1, 0, 0, 0, 0, 0.5")),
        Some("*CONTROL_SOLID"),
        Some("PSFAIL"),
        "erosion",
    );
    let e = err(&t.replacen("1, 0, 0, 0, 0, 0.5", "1, 0, 0, 0, 0, 0, 0, 1", 1));
    assert_eq!(e.field.as_deref(), Some("TET13K"), "{e}");
    let e = err(&t.replacen("50, 1, 0, 1, 2.0", "99, 1, 0, 1, 2.0", 1));
    assert_eq!(e.field.as_deref(), Some("PID"), "{e}");
    let e = err(&t.replacen("20\n2, 1\n", "20\n2, 7\n", 1));
    assert_eq!(e.field.as_deref(), Some("K"), "{e}");
    let e = err(&t.replacen(
        "*DATABASE_HISTORY_SOLID_SET\n20",
        "*DATABASE_HISTORY_SOLID_SET\n22",
        1,
    ));
    assert!(e.message.contains("solid set 22"), "{e}");
    let e = err(&t.replacen(
        "*CONSTRAINED_EXTRA_NODES_SET",
        "*CONSTRAINED_JOINT_SPHERICAL",
        1,
    ));
    assert!(e.message.contains("not supported"), "{e}");
    let e = err(&t.replacen(
        "*CONSTRAINED_NODAL_RIGID_BODY\n",
        "*CONSTRAINED_NODAL_RIGID_BODY_TITLE\n",
        1,
    ));
    assert!(e.message.contains("_SPC and _INERTIA"), "{e}");
}

/// `*HOURGLASS` and HGID on `*PART`: IHQ blank takes `*CONTROL_HOURGLASS`'s form, QM, Q1, Q2
/// blank their defaults 0.1, 1.5, 0.06; an HGID that no `*HOURGLASS` defines is an error naming
/// it and the line; IHQ 6 is refused naming the field.
#[test]
fn hourglass_cards_and_hgid() {
    let deck = with(
        "*PART\nblock\n1, 1, 1",
        "*HOURGLASS\n4, 5, 0.03, 0, 1.1, 0.2\n9\n*CONTROL_HOURGLASS\n4\n*PART\nblock\n1, 1, 1, , 9",
    );
    let m = parse(&deck);
    assert_eq!(m.parts[0].hourglass, Some(1));
    assert_eq!(m.parts[1].hourglass, None);
    assert_eq!(
        m.hourglass,
        vec![
            HourglassDef {
                id: 4,
                hourglass: Hourglass::Stiffness,
                qh: 0.03,
                q1: 1.1,
                q2: 0.2
            },
            HourglassDef {
                id: 9,
                hourglass: Hourglass::Stiffness,
                qh: 0.1,
                q1: 1.5,
                q2: 0.06
            },
        ]
    );
    let bad = with("*PART\nblock\n1, 1, 1", "*PART\nblock\n1, 1, 1, , 3");
    let e = err(&bad).to_string();
    assert!(e.contains("HGID") && e.contains('3'), "{e}");
    assert!(
        e.starts_with(&format!("t.k:{}:", line_of(&bad, "1, 1, 1, , 3"))),
        "{e}"
    );
    let e = err(&with("*PART\nblock", "*HOURGLASS\n4, 6\n*PART\nblock")).to_string();
    assert!(e.contains("IHQ") && e.contains("6 not supported"), "{e}");
}

/// `*CONTACT_AUTOMATIC_NODES_TO_SURFACE` reads as a one-way surface-to-surface contact (its
/// `_ID` form too); the writer writes the keyword back. (A node-set slave, SSTYP 4:
/// tests/contact_node_set.rs.)
#[test]
fn nodes_to_surface_contact() {
    let old = "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n1, 2, 3, 3";
    for kw in [
        "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n1, 2, 3, 3",
        "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n5, one way\n1, 2, 3, 3",
    ] {
        let m = parse(&with(old, kw));
        let c = m.contacts.last().unwrap();
        assert!(c.one_way && !c.single_surface, "{kw}: {c:?}");
        assert_eq!(c.master, Some(ContactSurface::Part(1)));
        let back = parse_deck(&write_deck(&m), "w.k").unwrap().model;
        assert!(back.contacts.last().unwrap().one_way);
    }
    assert!(!parse(BASE).contacts.last().unwrap().one_way);
}

/// `*MAT_ELASTIC_PLASTIC_HYDRO` (`*MAT_010`) with a Mie-Gruneisen EOS on its part reads as the
/// Johnson-Cook material with A = SIGY, B = EH, N = 1, no rate and no temperature terms, and the
/// same EOS and elastic constants (from G and K0): the same model as that `*MAT_JOHNSON_COOK`
/// deck, whose law is verified against its closed form. Errors: no EOS on its part, a pressure
/// cutoff, a pressure-dependent yield (A1), a hardening curve, erosion (FS).
#[test]
fn elastic_plastic_hydro_is_johnson_cook_without_rate_or_heat() {
    let eos = "*EOS_GRUNEISEN\n5, 4578., 1.33, 0., 0., 1.67, 0.43\n1.0\n";
    let hydro = format!("*MAT_ELASTIC_PLASTIC_HYDRO\n1, 7830., 8.18e10, 7.92e8, 2.1e9\n{eos}");
    let jc = format!(
        "*MAT_JOHNSON_COOK\n1, 7830., 8.18e10\n7.92e8, 2.1e9, 1.0, 0., 1., 0., 0., 1.0\n0.\n{eos}"
    );
    let deck = |mat: &str| {
        with("*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n", mat).replacen("1, 1, 1\n", "1, 1, 1, 5\n", 1)
    };
    let (a, b) = (parse(&deck(&hydro)), parse(&deck(&jc)));
    assert_eq!(a.materials[0], b.materials[0]);
    let MaterialKind::JohnsonCook(j) = a.materials[0].kind else {
        panic!("a Johnson-Cook material")
    };
    assert_eq!((j.a, j.b, j.n, j.c), (7.92e8, 2.1e9, 1.0, 0.0));
    assert!(j.eos.is_some() && j.rho_cp.is_infinite() && j.t_melt.is_infinite());
    let mat010 = deck(&hydro.replace("*MAT_ELASTIC_PLASTIC_HYDRO", "*MAT_010"));
    assert_eq!(parse(&mat010).materials[0], a.materials[0]);
    // FS erodes at that effective plastic strain (the separation group set aside)
    let eroding = parse(
        &deck(&hydro.replace("7.92e8, 2.1e9", "7.92e8, 2.1e9, 0., 0.5"))
            .replace("*MAT_ADD_SEPARATION", "*COMMENT"),
    );
    assert_eq!(eroding.erosion[0].rule.plastic_strain, Some(0.5));
    // errors
    let e = err(&deck(&hydro).replacen("1, 1, 1, 5\n", "1, 1, 1\n", 1));
    assert!(e.message.contains("*MAT_ELASTIC_PLASTIC_HYDRO"), "{e}");
    for (card, field) in [
        ("7.92e8, 2.1e9, -1e8", "PC"),
        ("7.92e8, 2.1e9, 0., -0.5", "FS"),
        ("7.92e8, 2.1e9\n1e3", "A1"),
        ("7.92e8, 2.1e9\n0., 0., 0.\n0., 0.1", "EPS"),
    ] {
        let e = err(&deck(&hydro.replace("7.92e8, 2.1e9", card)));
        assert_eq!(e.field.as_deref(), Some(field), "{card}: {e}");
    }
}

/// `*BOUNDARY_PRESCRIBED_MOTION_...` DOF 4 and -4 (along a `*DEFINE_VECTOR`), 5-7 and 8, -8
/// (a rigid body's rotations): what each reads as, a vector in a local system turned to
/// global axes, the refusals by name, and the writer's deck reading back the same.
#[test]
fn motions_along_vectors_and_rotations() {
    let motions = |cards: &str| {
        with(
            "*BOUNDARY_PRESCRIBED_MOTION_RIGID\n2, 1, 0, 1, 0.5\n",
            &format!(
                "*BOUNDARY_PRESCRIBED_MOTION_RIGID\n2, 1, 0, 1, 0.5\n{cards}\
                 *DEFINE_VECTOR\n7, 1., 1., 1., 1., 4., 5.\n\
                 *DEFINE_VECTOR_TITLE\nturned\n8, 0., 0., 0., 1., 0., 0., 3\n\
                 *DEFINE_COORDINATE_VECTOR\n3, 0., 1., 0., -1., 0., 0.\n"
            ),
        )
    };
    let t = motions(
        "2, -4, 0, 1, 2., 7\n2, 6, 0, 1, 3., 0, 1.5e-3, 1.0e-4\n2, -8, 0, 1, 1., 8, 1e28\n\
         2, 4, 2, 1, 1., 7, 2e-3\n",
    );
    let m = parse(&t);
    // DEATH and BIRTH: blank, 0 and 1e28 mean never and from the start
    let windows: Vec<Window> = m.prescribed[1..5].iter().map(|p| p.window).collect();
    let never = f64::INFINITY;
    assert_eq!(
        windows,
        vec![
            Window::ALWAYS,
            Window {
                birth: 1e-4,
                death: 1.5e-3
            },
            Window {
                birth: 0.0,
                death: never
            },
            Window {
                birth: 0.0,
                death: 2e-3
            },
        ]
    );
    let dofs: Vec<MotionDof> = m.prescribed[1..5].iter().map(|p| p.dof).collect();
    assert_eq!(
        dofs,
        vec![
            // (0, 3, 4) / 5
            MotionDof::Along {
                dir: [0.0, 0.6, 0.8],
                only: true
            },
            MotionDof::Rotation {
                dir: [0.0, 1.0, 0.0],
                only: false
            },
            // local x of system 3 is global y
            MotionDof::Rotation {
                dir: [0.0, 1.0, 0.0],
                only: true
            },
            MotionDof::Along {
                dir: [0.0, 0.6, 0.8],
                only: false
            },
        ]
    );
    assert_eq!(m.prescribed[4].vad, Vad::Displacement);
    // a direction of many digits comes back to round-off (written in full, not in 10 columns)
    let m2 = parse(&motions(
        "2, 4, 0, 1, 1., 9\n*DEFINE_VECTOR\n9, 0., 0., 0., 1., 2., 3.\n",
    ));
    let back = parse(&write_deck(&m2));
    let dir = |m: &Model| match m.prescribed[1].dof {
        MotionDof::Along { dir, .. } => dir,
        d => panic!("{d:?}"),
    };
    let (a, b) = (dir(&m2), dir(&back));
    assert!(
        (0..3).all(|i| (a[i] - b[i]).abs() <= 2e-16),
        "{a:?} vs {b:?}"
    );
    assert!((a[2] - 3.0 / 14f64.sqrt()).abs() <= 2e-16);
    // written and read back
    assert_eq!(
        format!("{:?}", parse(&write_deck(&m)).prescribed),
        format!("{:?}", m.prescribed)
    );
    // refusals, each naming its field
    for (cards, field, words) in [
        ("2, 4, 0, 1\n", "VID", "missing"),
        ("2, 4, 0, 1, 1., 9\n", "VID", "vector 9 is not defined"),
        ("2, 7, 2, 1\n", "VAD", "angular velocity"),
        ("2, 9, 0, 1\n", "DOF", "9 not supported"),
        ("2, 1, 2, 1, 1., 0, 0., 1e-4\n", "BIRTH", "VAD 2"),
        ("2, 1, 0, 1, 1., 0, 1e-4, 2e-4\n", "BIRTH", "before DEATH"),
        ("2, 1, 0, 1, 1., 0, 0., -1.\n", "BIRTH", "at least 0"),
    ] {
        let e = err(&motions(cards));
        assert_eq!(e.field.as_deref(), Some(field), "{cards}: {e}");
        assert!(e.message.contains(words), "{cards}: {e}");
    }
    let e = err(&with(
        "*BOUNDARY_PRESCRIBED_MOTION_SET\n1, 3, 2, 2\n",
        "*BOUNDARY_PRESCRIBED_MOTION_SET\n1, 5, 0, 2\n",
    ));
    assert!(
        e.field.as_deref() == Some("DOF") && e.message.contains("no rotational degrees of freedom"),
        "{e}"
    );
    let e = err(&with(
        "*BOUNDARY_PRESCRIBED_MOTION_RIGID\n",
        "*DEFINE_VECTOR\n7, 1., 1., 1., 1., 1., 1.\n*BOUNDARY_PRESCRIBED_MOTION_RIGID\n",
    ));
    assert!(e.message.contains("no direction"), "{e}");
    let e = err(&motions("2, 4, 0, 1, 1., 8\n")
        .replace("0., 0., 0., 1., 0., 0., 3", "0., 0., 0., 1., 0., 0., 4"));
    assert!(
        e.message.contains("coordinate system 4 is not defined"),
        "{e}"
    );
}

/// `*RIGIDWALL_PLANAR_FINITE` and `_ID`: the rectangle read (l made a unit vector in the plane),
/// written and read back, and the options cleave does not model refused by name.
#[test]
fn finite_walls_and_wall_options() {
    let wall = |kw: &str, extra: &str| {
        with(
            "*RIGIDWALL_PLANAR\n0\n0., 0., -0.1, 0., 0., 1., 0.5\n",
            &format!("{kw}\n0\n0., 0., -0.1, 0., 0., 1., 0.5\n{extra}"),
        )
    };
    // the edge vector from the tail to (3, 4, 7): its part along the normal (z) dropped
    let m = parse(&wall(
        "*RIGIDWALL_PLANAR_FINITE_ID\n7 floor",
        "3., 4., 7., 2.5, 1.5\n",
    ));
    let e = m.rigid_walls[0].extent.expect("finite");
    assert_eq!((e.l, e.len_l, e.len_m), ([0.6, 0.8, 0.0], 2.5, 1.5));
    assert_eq!(m.rigid_walls[1].extent, None);
    let back = parse(&write_deck(&m));
    let b = back.rigid_walls[0].extent.expect("written finite");
    assert!((0..3).all(|i| (b.l[i] - e.l[i]).abs() <= 1e-15), "{b:?}");
    assert_eq!((b.len_l, b.len_m), (2.5, 1.5));
    // an _ID card alone
    let m = parse(&wall("*RIGIDWALL_PLANAR_ID\n3", ""));
    assert_eq!(m.rigid_walls.len(), 2);
    for (kw, extra, words) in [
        ("*RIGIDWALL_PLANAR_MOVING", "100., 5.\n", "_MOVING"),
        ("*RIGIDWALL_PLANAR_ORTHO", "", "_ORTHO"),
        ("*RIGIDWALL_PLANAR_FINITE", "1., 0., 0., 0., 1.\n", "LENL"),
        (
            "*RIGIDWALL_PLANAR_FINITE",
            "0., 0., 5., 1., 1.\n",
            "along the wall's normal",
        ),
    ] {
        let e = err(&wall(kw, extra));
        assert!(e.to_string().contains(words), "{kw}: {e}");
    }
}

/// `*RIGIDWALL_GEOMETRIC_{SPHERE,CYLINDER,FLAT}` with `_MOTION`, `_DISPLAY` and `_ID`: what each
/// reads as, written and read back, and the refusals.
#[test]
fn geometric_walls() {
    let wall = |kw: &str, cards: &str| {
        with(
            "*RIGIDWALL_PLANAR\n0\n0., 0., -0.1, 0., 0., 1., 0.5\n",
            &format!("{kw}\n0\n0.1, 0.2, 0.3, 0.1, 0.2, 1.3, 0.25\n{cards}"),
        )
    };
    let m = parse(&wall(
        "*RIGIDWALL_GEOMETRIC_SPHERE_MOTION_DISPLAY_ID\n4 ball",
        "0.05\n1, 0, 0., 3., 4.\n9, 7800., 2e11, 0.3\n",
    ));
    let w = &m.rigid_walls[0];
    assert_eq!(w.shape, WallShape::Sphere { radius: 0.05 });
    assert_eq!(
        w.motion,
        Some(WallMotion {
            curve: 0,
            displacement: false,
            dir: [0.0, 0.6, 0.8]
        })
    );
    assert_eq!((w.tail, w.fric), ([0.1, 0.2, 0.3], 0.25));
    let back = parse(&write_deck(&m));
    assert_eq!(
        format!("{:?}", back.rigid_walls),
        format!("{:?}", m.rigid_walls)
    );
    // a cylinder: LENCYL blank is infinite
    let m = parse(&wall("*RIGIDWALL_GEOMETRIC_CYLINDER", "0.02\n"));
    assert_eq!(
        m.rigid_walls[0].shape,
        WallShape::Cylinder {
            radius: 0.02,
            length: f64::INFINITY
        }
    );
    let m = parse(&wall(
        "*RIGIDWALL_GEOMETRIC_CYLINDER_MOTION",
        "0.02, 0.5\n1, 1, 1.\n",
    ));
    let w = &m.rigid_walls[0];
    assert_eq!(
        w.shape,
        WallShape::Cylinder {
            radius: 0.02,
            length: 0.5
        }
    );
    assert!(w
        .motion
        .is_some_and(|mo| mo.displacement && mo.dir == [1.0, 0.0, 0.0]));
    assert_eq!(
        format!("{:?}", parse(&write_deck(&m)).rigid_walls),
        format!("{:?}", m.rigid_walls)
    );
    // FLAT: a finite plane
    let m = parse(&wall(
        "*RIGIDWALL_GEOMETRIC_FLAT",
        "1.1, 0.2, 0.3, 2., 3.\n",
    ));
    let w = &m.rigid_walls[0];
    assert_eq!(
        (w.shape, w.extent.map(|e| e.l)),
        (WallShape::Plane, Some([1.0, 0.0, 0.0]))
    );
    for (kw, cards, words) in [
        (
            "*RIGIDWALL_GEOMETRIC_PRISM",
            "1., 0., 0., 1., 1., 1.\n",
            "prism",
        ),
        ("*RIGIDWALL_GEOMETRIC_SPHERE", "0.\n", "RADSPH"),
        (
            "*RIGIDWALL_GEOMETRIC_SPHERE_MOTION",
            "0.1\n1, 2, 1.\n",
            "OPT",
        ),
        (
            "*RIGIDWALL_GEOMETRIC_SPHERE_MOTION",
            "0.1\n1, 0\n",
            "direction",
        ),
        (
            "*RIGIDWALL_GEOMETRIC_SPHERE_MOTION",
            "0.1\n8, 0, 1.\n",
            "curve 8",
        ),
        ("*RIGIDWALL_GEOMETRIC_SPHERE_FORCES", "0.1\n", "_FORCES"),
    ] {
        let e = err(&wall(kw, cards));
        assert!(e.to_string().contains(words), "{kw}: {e}");
    }
}

/// LCTM of `*CONTROL_TIMESTEP`: the curve of the largest time step, read, written and read
/// back; an undefined curve or one with a point at or below zero is an error naming LCTM.
#[test]
fn time_step_curve() {
    let m = parse(&with(
        "*CONTROL_TIMESTEP\n0.0, 0.8\n",
        "*CONTROL_TIMESTEP\n0.0, 0.8, 0, 0., 0., 2\n",
    ));
    assert_eq!(m.control.dt_max_curve, Some(1));
    assert_eq!(parse(&write_deck(&m)).control.dt_max_curve, Some(1));
    assert_eq!(parse(BASE).control.dt_max_curve, None);
    let e = err(&with(
        "*CONTROL_TIMESTEP\n0.0, 0.8\n",
        "*CONTROL_TIMESTEP\n0.0, 0.8, 0, 0., 0., 7\n",
    ));
    assert!(
        e.field.as_deref() == Some("LCTM") && e.message.contains("curve 7"),
        "{e}"
    );
    // curve 1 passes through 0 at t = 0 (0: no limit there); a negative step is an error
    let m = parse(&with(
        "*CONTROL_TIMESTEP\n0.0, 0.8\n",
        "*CONTROL_TIMESTEP\n0.0, 0.8, 0, 0., 0., 1\n",
    ));
    assert_eq!(m.control.dt_max_curve, Some(0));
    let e = err(&with(
        "*CONTROL_TIMESTEP\n0.0, 0.8\n",
        "*DEFINE_CURVE\n5\n0., -1.\n*CONTROL_TIMESTEP\n0.0, 0.8, 0, 0., 0., 5\n",
    ));
    assert!(e.message.contains("must not be negative"), "{e}");
}
