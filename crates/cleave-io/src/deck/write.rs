//! Writing a [`Model`] as a complete fixed-width LS-DYNA keyword deck (the inverse of the
//! reader): sets are written as they are, constraints and prescribed motion per node,
//! nonzero initial velocities as `*INITIAL_VELOCITY_NODE`, and each rigid wall that acts on
//! a node list without a matching node set gets a `*SET_NODE_LIST` of its own.
//!
//! Every real is formatted to the highest precision its field width allows (exactly, when
//! its shortest round-trip form fits); an integer too wide for its field makes that one card
//! comma-separated instead.

use std::fmt::Write as _;

use cleave_core::element::shape::{shape_of, Shape};
use cleave_core::material::{Eos, JohnsonCook, PiecewiseLinear};
use cleave_core::model::{
    ContactSurface, Hourglass, Material, MaterialKind, Model, MotionDof, MotionTarget, PenaltyRule,
    RigidWall, StrengthDist, TiedSlave, Vad, WallShape, Window,
};

/// One field of a card.
#[derive(Clone, Copy, Debug)]
pub(crate) enum F {
    I(i64),
    R(f64),
    /// A blank field (the reader's default).
    B,
}

/// The `$#` line naming the fields, aligned with them.
pub(crate) fn names(out: &mut String, names: &[&str], widths: &[usize]) {
    let mut line = String::from("$#");
    for (k, (n, &w)) in names.iter().zip(widths).enumerate() {
        let w = if k == 0 { w.saturating_sub(2) } else { w };
        let _ = write!(line, "{n:>w$}");
    }
    out.push_str(line.trim_end());
    out.push('\n');
}

/// Formats `v` in at most `w` characters with as much precision as fits.
pub fn fmt_f64(v: f64, w: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return "0.0".to_string();
    }
    let exact = [format!("{v:?}"), format!("{v:e}")];
    if let Some(s) = exact
        .into_iter()
        .filter(|s| s.len() <= w)
        .min_by_key(String::len)
    {
        return s;
    }
    // the more accurate of the scientific and fixed forms with the most digits that fit
    let mut best: Option<(f64, String)> = None;
    for s in [widest(v, w, true), widest(v, w, false)]
        .into_iter()
        .flatten()
    {
        let s = trim_zeros(&s);
        let err = s.parse::<f64>().map_or(f64::INFINITY, |x| (x - v).abs());
        let better = match &best {
            None => true,
            Some((e, b)) => err < *e || (err == *e && s.len() < b.len()),
        };
        if better {
            best = Some((err, s));
        }
    }
    best.map_or_else(|| format!("{v:.0e}"), |(_, s)| s)
}

/// `v` in scientific (`sci`) or fixed notation with as many decimals as fit in `w`.
fn widest(v: f64, w: usize, sci: bool) -> Option<String> {
    let fmt = |p: usize| {
        if sci {
            format!("{v:.p$e}")
        } else {
            format!("{v:.p$}")
        }
    };
    let base = fmt(0).len();
    if base > w {
        return None;
    }
    // one column for the decimal point; rounding may lengthen the result by one
    let mut p = (w - base).saturating_sub(1).min(17);
    loop {
        let s = fmt(p);
        if s.len() <= w {
            return Some(s);
        }
        p = p.checked_sub(1)?;
    }
}

/// Drops trailing zeros of the mantissa (keeping one digit after the point): same value.
fn trim_zeros(s: &str) -> String {
    let (mant, exp) = s.find('e').map_or((s, ""), |i| s.split_at(i));
    if !mant.contains('.') {
        return s.to_string();
    }
    let t = mant.trim_end_matches('0');
    let t = if t.ends_with('.') {
        &mant[..t.len() + 1]
    } else {
        t
    };
    format!("{t}{exp}")
}

/// Writes a card: fixed width if every field fits, comma-separated otherwise.
pub(crate) fn card(out: &mut String, fields: &[F], widths: &[usize]) {
    let text: Vec<String> = fields
        .iter()
        .zip(widths)
        .map(|(f, &w)| match *f {
            F::I(i) => i.to_string(),
            // wide fields keep a blank column so that neighbouring numbers stay readable
            F::R(r) => fmt_f64(r, if w >= 16 { w - 1 } else { w }),
            F::B => String::new(),
        })
        .collect();
    if text.iter().zip(widths).all(|(s, &w)| s.len() <= w) {
        let mut line = String::new();
        for (s, &w) in text.iter().zip(widths) {
            let _ = write!(line, "{s:>w$}");
        }
        out.push_str(line.trim_end());
    } else {
        out.push_str(&text.join(","));
    }
    out.push('\n');
}

/// Writes a card comma-separated with every real in its shortest exact form: for the unit
/// vectors (directions, edge vectors), which 10 columns would cut to 8 digits.
fn exact_card(out: &mut String, fields: &[F]) {
    let text: Vec<String> = fields
        .iter()
        .map(|f| match *f {
            F::I(i) => i.to_string(),
            F::R(r) => format!("{r:?}"),
            F::B => String::new(),
        })
        .collect();
    out.push_str(&text.join(", "));
    out.push('\n');
}

pub(crate) const W10: [usize; 8] = [10; 8];

/// A keyword with one card of 10-character fields.
fn simple(out: &mut String, kw: &str, n: &[&str], fields: &[F]) {
    out.push_str(kw);
    out.push('\n');
    names(out, n, &W10);
    card(out, fields, &W10);
}

/// Ids 8 per card in 10-character fields.
pub(crate) fn id_cards(out: &mut String, ids: impl IntoIterator<Item = i64>) {
    let ids: Vec<F> = ids.into_iter().map(F::I).collect();
    for chunk in ids.chunks(8) {
        card(out, chunk, &W10);
    }
}

/// A title line: at most 80 characters, never read as a comment or keyword.
pub(crate) fn title_line(t: &str) -> String {
    t.trim_start_matches(['$', '*', ' '])
        .chars()
        .filter(|c| !c.is_control())
        .take(80)
        .collect()
}

/// The complete deck for `model`.
pub fn write_deck(model: &Model) -> String {
    let mut o = String::new();
    o.push_str("$ LS-DYNA keyword deck written by cleave\n");
    let _ = writeln!(
        o,
        "$ {} nodes, {} solid elements, {} parts",
        model.num_nodes(),
        model.num_elements(),
        model.parts.len()
    );
    o.push_str("*KEYWORD\n");
    let title = title_line(&model.title);
    if !title.trim().is_empty() {
        let _ = writeln!(o, "*TITLE\n{title}");
    }
    controls(&mut o, model);
    properties(&mut o, model);
    mesh(&mut o, model);
    let wall_sets = sets(&mut o, model);
    rigid_bodies(&mut o, model);
    curves(&mut o, model);
    conditions(&mut o, model);
    interactions(&mut o, model, &wall_sets);
    o.push_str("*END\n");
    o
}

fn controls(o: &mut String, m: &Model) {
    let c = &m.control;
    // DTMIN only when it is not cleave's default floor (which a blank field means)
    if c.dt_min == cleave_core::model::DEFAULT_DTMIN {
        simple(o, "*CONTROL_TERMINATION", &["endtim"], &[F::R(c.end_time)]);
    } else {
        simple(
            o,
            "*CONTROL_TERMINATION",
            &["endtim", "endcyc", "dtmin"],
            &[F::R(c.end_time), F::B, F::R(c.dt_min)],
        );
    }
    match c.dt_max_curve {
        None => simple(
            o,
            "*CONTROL_TIMESTEP",
            &["dtinit", "tssfac"],
            &[F::R(c.dt_init), F::R(c.tssfac)],
        ),
        Some(k) => simple(
            o,
            "*CONTROL_TIMESTEP",
            &["dtinit", "tssfac", "isdo", "tslimt", "dt2ms", "lctm"],
            &[
                F::R(c.dt_init),
                F::R(c.tssfac),
                F::B,
                F::B,
                F::B,
                F::I(m.curves[k].id),
            ],
        ),
    }
    let ihq = match c.hourglass {
        Hourglass::Viscous => 1,
        Hourglass::Stiffness => 4,
    };
    simple(
        o,
        "*CONTROL_HOURGLASS",
        &["ihq", "qh"],
        &[F::I(ihq), F::R(c.qh)],
    );
    simple(
        o,
        "*CONTROL_BULK_VISCOSITY",
        &["q1", "q2"],
        &[F::R(c.q1), F::R(c.q2)],
    );
    let penopt = match c.penalty {
        PenaltyRule::Smaller => 1,
        PenaltyRule::Face => 2,
    };
    simple(
        o,
        "*CONTROL_CONTACT",
        &["slsfac", "rwpnal", "islchk", "shlthk", "penopt"],
        &[F::R(c.slsfac), F::B, F::B, F::B, F::I(penopt)],
    );
    let r = &m.output;
    for (kw, dt) in [
        ("*DATABASE_GLSTAT", r.glstat_dt),
        ("*DATABASE_NODOUT", r.nodout_dt),
        ("*DATABASE_ELOUT", r.elout_dt),
        ("*DATABASE_RWFORC", r.rwforc_dt),
        ("*DATABASE_RCFORC", r.rcforc_dt),
        ("*DATABASE_BINARY_D3PLOT", r.d3plot_dt),
    ] {
        if dt > 0.0 {
            simple(o, kw, &["dt"], &[F::R(dt)]);
        }
    }
    if !r.history_nodes.is_empty() {
        o.push_str("*DATABASE_HISTORY_NODE\n");
        id_cards(o, r.history_nodes.iter().map(|&n| m.node_ids[n as usize]));
    }
    if !r.history_solids.is_empty() {
        o.push_str("*DATABASE_HISTORY_SOLID\n");
        id_cards(o, r.history_solids.iter().map(|&e| m.elem_ids[e as usize]));
    }
}

/// A finite value, or a blank field for "none" (the reader's default).
fn finite_or_blank(v: f64) -> F {
    if v.is_finite() {
        F::R(v)
    } else {
        F::B
    }
}

/// Johnson-Cook: `*MAT_JOHNSON_COOK` when it softens thermally, heats or has an equation of
/// state (what `*MAT_098` cannot say; the EOS is written after it with the material's id, and
/// its parts name it), else `*MAT_SIMPLIFIED_JOHNSON_COOK` (which carries the caps SIGMAX,
/// SIGSAT).
/// `*MAT_015` (with temperature, an EOS or damage) or else `*MAT_098`; the erosion rule's
/// damage goes on `*MAT_015`'s D1-D5 and EFMIN, its plastic strain on `*MAT_098`'s PSFAIL.
/// Returns whether the plastic strain at failure was written.
fn johnson_cook(
    o: &mut String,
    mat: &Material,
    jc: &JohnsonCook,
    erosion: Option<&cleave_core::erosion::ErosionRule>,
) -> bool {
    let hardening = [F::R(jc.a), F::R(jc.b), F::R(jc.n), F::R(jc.c)];
    let damage = erosion.and_then(|r| r.johnson_cook);
    let fail = erosion.and_then(|r| r.plastic_strain);
    if jc.t_melt.is_finite() || jc.rho_cp.is_finite() || jc.eos.is_some() || damage.is_some() {
        simple(
            o,
            "*MAT_JOHNSON_COOK",
            &["mid", "ro", "g", "e", "pr"],
            &[
                F::I(mat.id),
                F::R(mat.density),
                F::R(mat.shear_modulus()),
                // with an EOS, E and PR follow from G and its bulk modulus: left blank
                if jc.eos.is_some() {
                    F::B
                } else {
                    F::R(mat.young)
                },
                if jc.eos.is_some() {
                    F::B
                } else {
                    F::R(mat.poisson)
                },
            ],
        );
        names(o, &["a", "b", "n", "c", "m", "tm", "tr", "epso"], &W10);
        let mut f = hardening.to_vec();
        f.extend([
            F::R(jc.m),
            finite_or_blank(jc.t_melt),
            F::R(jc.t_room),
            F::R(jc.eps0),
        ]);
        card(o, &f, &W10);
        let cp = finite_or_blank(jc.rho_cp / mat.density);
        match damage {
            None => {
                names(o, &["cp"], &W10);
                card(o, &[cp], &W10);
            }
            Some(d) => {
                names(
                    o,
                    &["cp", "pc", "spall", "it", "d1", "d2", "d3", "d4"],
                    &W10,
                );
                let mut f = vec![cp, F::B, F::B, F::B];
                f.extend(d.d[..4].iter().map(|&v| F::R(v)));
                card(o, &f, &W10);
                names(o, &["d5", "c2/p", "erod", "efmin"], &W10);
                card(o, &[F::R(d.d[4]), F::B, F::B, F::R(d.efmin)], &W10);
            }
        }
        if let Some(eos) = jc.eos {
            equation_of_state(o, mat.id, &eos);
        }
        false
    } else {
        simple(
            o,
            "*MAT_SIMPLIFIED_JOHNSON_COOK",
            &["mid", "ro", "e", "pr"],
            &[
                F::I(mat.id),
                F::R(mat.density),
                F::R(mat.young),
                F::R(mat.poisson),
            ],
        );
        names(
            o,
            &["a", "b", "n", "c", "psfail", "sigmax", "sigsat", "epso"],
            &W10,
        );
        let mut f = hardening.to_vec();
        f.extend([
            fail.map_or(F::B, F::R),
            finite_or_blank(jc.sig_max),
            finite_or_blank(jc.sig_sat),
            F::R(jc.eps0),
        ]);
        card(o, &f, &W10);
        true
    }
}

/// `*EOS_LINEAR_POLYNOMIAL` or `*EOS_GRUNEISEN` with id `id`.
fn equation_of_state(o: &mut String, id: i64, eos: &Eos) {
    match *eos {
        Eos::LinearPolynomial { c, e0, v0 } => {
            o.push_str("*EOS_LINEAR_POLYNOMIAL\n");
            names(
                o,
                &["eosid", "c0", "c1", "c2", "c3", "c4", "c5", "c6"],
                &W10,
            );
            let mut f = vec![F::I(id)];
            f.extend(c.iter().map(|&v| F::R(v)));
            card(o, &f, &W10);
            names(o, &["e0", "v0"], &W10);
            card(o, &[F::R(e0), F::R(v0)], &W10);
        }
        Eos::Gruneisen {
            c,
            s,
            gamma0,
            a,
            e0,
            v0,
            ..
        } => {
            o.push_str("*EOS_GRUNEISEN\n");
            names(
                o,
                &["eosid", "c", "s1", "s2", "s3", "gamao", "a", "e0"],
                &W10,
            );
            let f = [
                F::I(id),
                F::R(c),
                F::R(s[0]),
                F::R(s[1]),
                F::R(s[2]),
                F::R(gamma0),
                F::R(a),
                F::R(e0),
            ];
            card(o, &f, &W10);
            names(o, &["v0"], &W10);
            card(o, &[F::R(v0)], &W10);
        }
    }
}

/// `*MAT_PIECEWISE_LINEAR_PLASTICITY`: the deck curve LCSS where the law came from one (it is
/// written with the curves), else the points as EPS/ES (at most 8: a law of more points and no
/// curve, which only a program can make, is written with its first 8 and a comment saying so).
/// `*MAT_ADD_EROSION` of material `mid` with the criteria of `r` (its plastic strain goes on
/// the material's card).
fn add_erosion(o: &mut String, mid: i64, r: &cleave_core::erosion::ErosionRule) {
    let opt = |v: Option<f64>| v.map_or(F::B, F::R);
    o.push_str("*MAT_ADD_EROSION\n");
    names(
        o,
        &[
            "mid", "excl", "mxpres", "mneps", "effeps", "voleps", "numfip", "ncs",
        ],
        &W10,
    );
    let c1 = [
        F::I(mid),
        F::B,
        opt(r.max_pressure),
        opt(r.min_principal_strain),
        opt(r.effective_strain),
        opt(r.volumetric_strain),
        F::B,
        F::I(i64::from(r.ncs.max(1))),
    ];
    card(o, &c1, &W10);
    names(
        o,
        &[
            "mnpres", "sigp1", "sigvm", "mxeps", "epssh", "sigth", "impulse", "failtm",
        ],
        &W10,
    );
    let c2 = [
        opt(r.min_pressure),
        opt(r.max_principal),
        opt(r.max_von_mises),
        opt(r.max_principal_strain),
        F::B,
        F::B,
        F::B,
        opt(r.failure_time),
    ];
    card(o, &c2, &W10);
}

/// `*MAT_024`, with FAIL = `fail` when the material erodes at a plastic strain.
fn piecewise(o: &mut String, mat: &Material, p: &PiecewiseLinear, fail: Option<f64>) {
    let mut f = vec![
        F::I(mat.id),
        F::R(mat.density),
        F::R(mat.young),
        F::R(mat.poisson),
        F::R(p.points.first().map_or(0.0, |q| q[1])),
    ];
    let mut n = vec!["mid", "ro", "e", "pr", "sigy"];
    if let Some(fail) = fail {
        f.extend([F::B, F::R(fail)]);
        n.extend(["etan", "fail"]);
    }
    simple(o, "*MAT_PIECEWISE_LINEAR_PLASTICITY", &n, &f);
    names(o, &["c", "p", "lcss"], &W10);
    let (c, pp) = if p.c > 0.0 {
        (F::R(p.c), F::R(p.p))
    } else {
        (F::B, F::B)
    };
    card(o, &[c, pp, p.lcss.map_or(F::B, F::I)], &W10);
    if let (Some(id), Some(t)) = (p.lcss, &p.table) {
        // the table, naming its curves (written with the others)
        simple(o, "*DEFINE_TABLE_2D", &["tbid"], &[F::I(id)]);
        names(o, &["value", "lcid"], &[20, 20]);
        for (v, (lcid, _)) in t.values.iter().zip(&t.curves) {
            card(o, &[F::R(*v), F::I(*lcid)], &[20, 20]);
        }
    }
    if p.lcss.is_none() {
        if p.points.len() > 8 {
            let _ = writeln!(
                o,
                "$ cleave: the hardening curve has {} points; EPS/ES hold the first 8",
                p.points.len()
            );
        }
        let pts = &p.points[..p.points.len().min(8)];
        names(o, &["eps1", "eps2", "..."], &W10);
        card(o, &pts.iter().map(|q| F::R(q[0])).collect::<Vec<_>>(), &W10);
        names(o, &["es1", "es2", "..."], &W10);
        card(o, &pts.iter().map(|q| F::R(q[1])).collect::<Vec<_>>(), &W10);
    }
}

fn properties(o: &mut String, m: &Model) {
    let given = |k: usize| m.part_inertia.iter().find(|pi| pi.part == k);
    let mut last_kw = "";
    for (k, p) in m.parts.iter().enumerate() {
        let kw = if given(k).is_some() {
            "*PART_INERTIA\n"
        } else {
            "*PART\n"
        };
        if kw != last_kw {
            o.push_str(kw);
            last_kw = kw;
        }
        o.push_str("$# title\n");
        let _ = writeln!(o, "{}", title_line(&p.title));
        let material = &m.materials[p.material];
        let (s, mat) = (m.sections[p.section].id, material.id);
        // an equation of state is written with its material's id (EOSID only then, so that
        // decks without one keep the three-field card)
        let eos = matches!(
            material.kind,
            MaterialKind::JohnsonCook(JohnsonCook { eos: Some(_), .. })
        );
        match (eos, p.hourglass) {
            (_, Some(h)) => {
                let e = if eos { F::I(mat) } else { F::B };
                let h = F::I(m.hourglass[h].id);
                names(o, &["pid", "secid", "mid", "eosid", "hgid"], &W10);
                card(o, &[F::I(p.id), F::I(s), F::I(mat), e, h], &W10);
            }
            (true, None) => {
                names(o, &["pid", "secid", "mid", "eosid"], &W10);
                card(o, &[F::I(p.id), F::I(s), F::I(mat), F::I(mat)], &W10);
            }
            (false, None) => {
                names(o, &["pid", "secid", "mid"], &W10);
                card(o, &[F::I(p.id), F::I(s), F::I(mat)], &W10);
            }
        }
        if let Some(pi) = given(k) {
            inertia_cards(o, &pi.given, true);
        }
    }
    if !m.hourglass.is_empty() {
        o.push_str("*HOURGLASS\n");
        names(o, &["hgid", "ihq", "qm", "ibq", "q1", "q2"], &W10);
        for h in &m.hourglass {
            let ihq = match h.hourglass {
                Hourglass::Viscous => 1,
                Hourglass::Stiffness => 4,
            };
            let f = [
                F::I(h.id),
                F::I(ihq),
                F::R(h.qh),
                F::B,
                F::R(h.q1),
                F::R(h.q2),
            ];
            card(o, &f, &W10);
        }
    }
    if !m.sections.is_empty() {
        o.push_str("*SECTION_SOLID\n");
        names(o, &["secid", "elform"], &W10);
        for s in &m.sections {
            card(o, &[F::I(s.id), F::I(s.elform as i64)], &W10);
        }
    }
    for (k, mat) in m.materials.iter().enumerate() {
        let erosion = m.erosion.iter().find(|d| d.material == k).map(|d| &d.rule);
        let fail = erosion.and_then(|r| r.plastic_strain);
        let mut fail_written = matches!(
            mat.kind,
            MaterialKind::PlasticKinematic { .. } | MaterialKind::PiecewiseLinear(_)
        );
        let common = [
            F::I(mat.id),
            F::R(mat.density),
            F::R(mat.young),
            F::R(mat.poisson),
        ];
        match mat.kind {
            MaterialKind::Elastic => simple(o, "*MAT_ELASTIC", &["mid", "ro", "e", "pr"], &common),
            MaterialKind::PlasticKinematic { sigy, etan, beta } => {
                let f = [
                    common[0],
                    common[1],
                    common[2],
                    common[3],
                    F::R(sigy),
                    F::R(etan),
                    F::R(beta),
                ];
                simple(
                    o,
                    "*MAT_PLASTIC_KINEMATIC",
                    &["mid", "ro", "e", "pr", "sigy", "etan", "beta"],
                    &f,
                );
                if let Some(fs) = fail {
                    names(o, &["src", "srp", "fs"], &W10);
                    card(o, &[F::B, F::B, F::R(fs)], &W10);
                }
            }
            MaterialKind::JohnsonCook(jc) => fail_written = johnson_cook(o, mat, &jc, erosion),
            MaterialKind::PiecewiseLinear(ref p) => piecewise(o, mat, p, fail),
            MaterialKind::Rigid { cmo, con1, con2 } => {
                simple(o, "*MAT_RIGID", &["mid", "ro", "e", "pr"], &common);
                names(o, &["cmo", "con1", "con2"], &W10);
                card(
                    o,
                    &[F::I(cmo as i64), F::I(con1 as i64), F::I(con2 as i64)],
                    &W10,
                );
            }
        }
        if fail.is_some() && !fail_written {
            let _ = writeln!(
                o,
                "$ cleave: material {} erodes at a plastic strain, which this card does not hold; not written",
                mat.id
            );
        }
        if let Some(r) = erosion.filter(|r| r.criteria() > 0) {
            add_erosion(o, mat.id, r);
        }
    }
    if !m.separations.is_empty() {
        o.push_str("*MAT_ADD_SEPARATION\n");
        names(
            o,
            &[
                "mid", "model", "sigmax", "beta", "gc", "bond", "dist", "seed",
            ],
            &W10,
        );
        for s in &m.separations {
            let (dist, seed, card2) = match s.strength {
                StrengthDist::Constant => (0, 0, None),
                StrengthDist::Uniform { smin, smax, seed } => {
                    (1, seed, Some([F::R(smin), F::R(smax), F::B, F::B]))
                }
                StrengthDist::Weibull {
                    m,
                    aref,
                    smin,
                    seed,
                } => (2, seed, Some([F::R(smin), F::B, F::R(m), F::R(aref)])),
            };
            let f = [
                F::I(m.materials[s.material].id),
                F::I(s.model as i64),
                F::R(s.sigmax),
                F::R(s.beta),
                F::R(s.gc),
                F::I(s.bond as i64),
                F::I(dist),
                F::I(seed as i64),
            ];
            card(o, &f, &W10);
            if let Some(c2) = card2 {
                card(o, &c2, &W10);
            }
        }
    }
}

fn mesh(o: &mut String, m: &Model) {
    const NODE: [usize; 6] = [8, 16, 16, 16, 8, 8];
    o.push_str("*NODE\n");
    names(o, &["nid", "x", "y", "z", "tc", "rc"], &NODE);
    for (id, x) in m.node_ids.iter().zip(&m.x0) {
        card(o, &[F::I(*id), F::R(x[0]), F::R(x[1]), F::R(x[2])], &NODE);
    }
    const ELEM: [usize; 10] = [8; 10];
    o.push_str("*ELEMENT_SOLID\n");
    names(
        o,
        &["eid", "pid", "n1", "n2", "n3", "n4", "n5", "n6", "n7", "n8"],
        &ELEM,
    );
    for ((id, c), &p) in m.elem_ids.iter().zip(&m.conn).zip(&m.elem_part) {
        let mut f = vec![F::I(*id), F::I(m.parts.get(p as usize).map_or(0, |p| p.id))];
        // a tetrahedron as LS-DYNA writes it, N1 N2 N3 N4 N4 N4 N4 N4
        let c = match shape_of(c) {
            Some(Shape::Tet) => [c[0], c[1], c[2], c[4], c[4], c[4], c[4], c[4]],
            _ => *c,
        };
        f.extend(c.iter().map(|&n| F::I(m.node_ids[n as usize])));
        card(o, &f, &ELEM);
    }
}

/// The inertia cards of `*PART_INERTIA` (`part`: with IRCS 0) or of
/// `*CONSTRAINED_NODAL_RIGID_BODY_INERTIA`.
fn inertia_cards(o: &mut String, g: &cleave_core::model::GivenInertia, part: bool) {
    let c = g.centre;
    if part {
        names(o, &["xc", "yc", "zc", "tm", "ircs", "nodeid"], &W10);
        card(
            o,
            &[F::R(c[0]), F::R(c[1]), F::R(c[2]), F::R(g.mass), F::I(0)],
            &W10,
        );
    } else {
        names(o, &["xc", "yc", "zc", "tm", "nid"], &W10);
        card(o, &[F::R(c[0]), F::R(c[1]), F::R(c[2]), F::R(g.mass)], &W10);
    }
    let t = g.inertia;
    names(o, &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"], &W10);
    card(
        o,
        &[t[0][0], t[0][1], t[0][2], t[1][1], t[1][2], t[2][2]].map(F::R),
        &W10,
    );
    let (v, w) = (g.velocity, g.omega);
    names(o, &["vtx", "vty", "vtz", "vrx", "vry", "vrz"], &W10);
    card(o, &[v[0], v[1], v[2], w[0], w[1], w[2]].map(F::R), &W10);
}

/// `*CONSTRAINED_NODAL_RIGID_BODY[_SPC][_INERTIA]` and `*CONSTRAINED_EXTRA_NODES_...`.
fn rigid_bodies(o: &mut String, m: &Model) {
    for b in &m.nodal_rigid {
        let spc = b.cmo != 0 || b.con1 != 0 || b.con2 != 0;
        let _ = writeln!(
            o,
            "*CONSTRAINED_NODAL_RIGID_BODY{}{}",
            if spc { "_SPC" } else { "" },
            if b.inertia.is_some() { "_INERTIA" } else { "" }
        );
        names(o, &["pid", "cid", "nsid"], &W10);
        card(o, &[F::I(b.id), F::B, F::I(m.node_sets[b.set].id)], &W10);
        if spc {
            names(o, &["cmo", "con1", "con2"], &W10);
            card(
                o,
                &[F::I(b.cmo as i64), F::I(b.con1 as i64), F::I(b.con2 as i64)],
                &W10,
            );
        }
        if let Some(g) = &b.inertia {
            inertia_cards(o, g, false);
        }
    }
    for x in &m.extra_nodes {
        let pid = m.parts[x.part].id;
        let iflag = F::I(x.iflag as i64);
        match x.set {
            Some(s) => {
                simple(
                    o,
                    "*CONSTRAINED_EXTRA_NODES_SET",
                    &["pid", "nsid", "iflag"],
                    &[F::I(pid), F::I(m.node_sets[s].id), iflag],
                );
            }
            None => {
                o.push_str("*CONSTRAINED_EXTRA_NODES_NODE\n");
                names(o, &["pid", "nid", "iflag"], &W10);
                for &n in &x.nodes {
                    card(o, &[F::I(pid), F::I(m.node_ids[n as usize]), iflag], &W10);
                }
            }
        }
    }
}

/// Writes the sets; returns the node set id of each rigid wall (0: all nodes).
fn sets(o: &mut String, m: &Model) -> Vec<i64> {
    let nid = |n: &u32| m.node_ids[*n as usize];
    let write_nodes = |o: &mut String, id: i64, nodes: &[u32]| {
        o.push_str("*SET_NODE_LIST\n");
        names(o, &["sid"], &W10);
        card(o, &[F::I(id)], &W10);
        id_cards(o, nodes.iter().map(nid));
    };
    for s in &m.node_sets {
        write_nodes(o, s.id, &s.nodes);
    }
    let mut next = m.node_sets.iter().map(|s| s.id).max().unwrap_or(0) + 1;
    let mut extra: Vec<(i64, &Vec<u32>)> = Vec::new();
    let mut wall_sets = Vec::new();
    for w in &m.rigid_walls {
        let id = match &w.nodes {
            None => 0,
            Some(nodes) => {
                let known = m
                    .node_sets
                    .iter()
                    .map(|s| (s.id, &s.nodes))
                    .chain(extra.iter().copied());
                match known.clone().find(|(_, n)| *n == nodes) {
                    Some((id, _)) => id,
                    None => {
                        write_nodes(o, next, nodes);
                        extra.push((next, nodes));
                        next += 1;
                        next - 1
                    }
                }
            }
        };
        wall_sets.push(id);
    }
    for s in &m.part_sets {
        o.push_str("*SET_PART_LIST\n");
        names(o, &["sid"], &W10);
        card(o, &[F::I(s.id)], &W10);
        id_cards(o, s.parts.iter().map(|&p| m.parts[p].id));
    }
    for s in &m.solid_sets {
        o.push_str("*SET_SOLID\n");
        names(o, &["sid"], &W10);
        card(o, &[F::I(s.id)], &W10);
        id_cards(o, s.elems.iter().map(|&e| m.elem_ids[e as usize]));
    }
    for s in &m.segment_sets {
        o.push_str("*SET_SEGMENT\n");
        names(o, &["sid"], &W10);
        card(o, &[F::I(s.id)], &W10);
        names(o, &["n1", "n2", "n3", "n4"], &W10);
        for seg in &s.segments {
            card(o, &seg.map(|n| F::I(nid(&n))), &W10);
        }
    }
    wall_sets
}

fn curves(o: &mut String, m: &Model) {
    for c in &m.curves {
        simple(
            o,
            "*DEFINE_CURVE",
            &["lcid", "sidr", "sfa", "sfo", "offa", "offo"],
            &[F::I(c.id)],
        );
        names(o, &["a1", "o1"], &[20, 20]);
        for (t, y) in c.t.iter().zip(&c.y) {
            card(o, &[F::R(*t), F::R(*y)], &[20, 20]);
        }
    }
}

fn conditions(o: &mut String, m: &Model) {
    let nid = |n: u32| m.node_ids[n as usize];
    if !m.spcs.is_empty() {
        o.push_str("*BOUNDARY_SPC_NODE\n");
        names(
            o,
            &[
                "nid", "cid", "dofx", "dofy", "dofz", "dofrx", "dofry", "dofrz",
            ],
            &W10,
        );
        for s in &m.spcs {
            let mut f = vec![F::I(nid(s.node)), F::I(0)];
            f.extend(s.dof.iter().map(|&d| F::I(d as i64)));
            card(o, &f, &W10);
        }
    }
    // the directions of DOF 4 and 8 as *DEFINE_VECTOR, numbered from 1 in order (DOF 5-7
    // are the rotations about the global axes)
    let mut vectors: Vec<[f64; 3]> = Vec::new();
    let dofs: Vec<(i64, i64)> = m
        .prescribed
        .iter()
        .map(|p| {
            let axis = |d: &[f64; 3]| (0..3).find(|&a| d[a] == 1.0 && d.iter().sum::<f64>() == 1.0);
            let mut vid = |d: [f64; 3]| {
                vectors.push(d);
                vectors.len() as i64
            };
            match p.dof {
                MotionDof::Axis(a) => (a as i64 + 1, 0),
                MotionDof::Rotation { dir, only: false } if axis(&dir).is_some() => {
                    (axis(&dir).unwrap_or(0) as i64 + 5, 0)
                }
                MotionDof::Along { dir, only } => (if only { -4 } else { 4 }, vid(dir)),
                MotionDof::Rotation { dir, only } => (if only { -8 } else { 8 }, vid(dir)),
            }
        })
        .collect();
    if !vectors.is_empty() {
        o.push_str("*DEFINE_VECTOR\n");
        names(o, &["vid", "xt", "yt", "zt", "xh", "yh", "zh"], &W10);
        for (k, d) in vectors.iter().enumerate() {
            let f = [
                F::I(k as i64 + 1),
                F::R(0.0),
                F::R(0.0),
                F::R(0.0),
                F::R(d[0]),
                F::R(d[1]),
                F::R(d[2]),
            ];
            exact_card(o, &f);
        }
    }
    let mut last_kw = "";
    for (p, &(dof, vid)) in m.prescribed.iter().zip(&dofs) {
        let (kw, id) = match p.target {
            MotionTarget::Node(n) => ("*BOUNDARY_PRESCRIBED_MOTION_NODE", nid(n)),
            MotionTarget::Rigid(part) => ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", m.parts[part].id),
            MotionTarget::NodalRigid(k) => {
                ("*BOUNDARY_PRESCRIBED_MOTION_RIGID", m.nodal_rigid[k].id)
            }
        };
        if kw != last_kw {
            o.push_str(kw);
            o.push('\n');
            names(
                o,
                &["id", "dof", "vad", "lcid", "sf", "vid", "death", "birth"],
                &W10,
            );
            last_kw = kw;
        }
        let vad = match p.vad {
            Vad::Velocity => 0,
            Vad::Displacement => 2,
        };
        let mut f = vec![
            F::I(id),
            F::I(dof),
            F::I(vad),
            F::I(m.curves[p.curve].id),
            F::R(p.sf),
        ];
        let timed = p.window != Window::ALWAYS;
        if vid > 0 || timed {
            f.push(F::I(vid));
        }
        if timed {
            let death = if p.window.death.is_finite() {
                p.window.death
            } else {
                1e28
            };
            f.extend([F::R(death), F::R(p.window.birth)]);
        }
        card(o, &f, &W10);
    }
    if m.v0.iter().any(|v| v.iter().any(|&x| x != 0.0)) {
        o.push_str("*INITIAL_VELOCITY_NODE\n");
        names(o, &["nid", "vx", "vy", "vz"], &W10);
        for (i, v) in m.v0.iter().enumerate() {
            if v.iter().any(|&x| x != 0.0) {
                card(
                    o,
                    &[F::I(m.node_ids[i]), F::R(v[0]), F::R(v[1]), F::R(v[2])],
                    &W10,
                );
            }
        }
    }
    for b in &m.body_loads {
        let kw = ["*LOAD_BODY_X", "*LOAD_BODY_Y", "*LOAD_BODY_Z"][b.axis.min(2)];
        let lcid = b.curve.map_or(0, |c| m.curves[c].id);
        simple(o, kw, &["lcid", "sf"], &[F::I(lcid), F::R(b.sf)]);
    }
    if !m.node_loads.is_empty() {
        o.push_str("*LOAD_NODE_POINT\n");
        names(o, &["nid", "dof", "lcid", "sf"], &W10);
        for l in &m.node_loads {
            let f = [
                F::I(m.node_ids[l.node as usize]),
                F::I(l.axis as i64 + 1),
                F::I(m.curves[l.curve].id),
                F::R(l.sf),
            ];
            card(o, &f, &W10);
        }
    }
    if !m.pressure_loads.is_empty() {
        o.push_str("*LOAD_SEGMENT\n");
        names(o, &["lcid", "sf", "at", "n1", "n2", "n3", "n4"], &W10);
        for l in &m.pressure_loads {
            let mut f = vec![F::I(m.curves[l.curve].id), F::R(l.sf), F::R(l.at)];
            f.extend(l.nodes.iter().map(|&n| F::I(m.node_ids[n as usize])));
            card(o, &f, &W10);
        }
    }
}

fn surface(m: &Model, s: Option<&ContactSurface>) -> (F, F) {
    match s {
        None | Some(ContactSurface::All) => (F::I(0), F::I(2)),
        Some(ContactSurface::SegmentSet(i)) => (F::I(m.segment_sets[*i].id), F::I(0)),
        Some(ContactSurface::PartSet(i)) => (F::I(m.part_sets[*i].id), F::I(2)),
        Some(ContactSurface::Part(i)) => (F::I(m.parts[*i].id), F::I(3)),
    }
}

/// A `*RIGIDWALL_GEOMETRIC_...` wall: a sphere, a cylinder, or a finite plane (FLAT), with
/// its `_MOTION`.
fn geometric_wall(o: &mut String, m: &Model, w: &RigidWall, nsid: i64) {
    let kind = match w.shape {
        WallShape::Plane => "FLAT",
        WallShape::Sphere { .. } => "SPHERE",
        WallShape::Cylinder { .. } => "CYLINDER",
    };
    let motion = if w.motion.is_some() { "_MOTION" } else { "" };
    simple(
        o,
        &format!("*RIGIDWALL_GEOMETRIC_{kind}{motion}"),
        &["nsid"],
        &[F::I(nsid)],
    );
    names(o, &["xt", "yt", "zt", "xh", "yh", "zh", "fric"], &W10);
    let f = [
        w.tail[0], w.tail[1], w.tail[2], w.head[0], w.head[1], w.head[2], w.fric,
    ]
    .map(F::R);
    card(o, &f, &W10);
    match w.shape {
        WallShape::Plane => {
            // a moving wall is a finite one (the reader makes FLAT walls finite)
            let e = w.extent.unwrap_or(cleave_core::model::WallExtent {
                l: [1.0, 0.0, 0.0],
                len_l: 1e20,
                len_m: 1e20,
            });
            names(o, &["xhev", "yhev", "zhev", "lenl", "lenm"], &W10);
            let hev = cleave_core::math::add(w.tail, e.l);
            exact_card(o, &[hev[0], hev[1], hev[2], e.len_l, e.len_m].map(F::R));
        }
        WallShape::Sphere { radius } => {
            names(o, &["radsph"], &W10);
            card(o, &[F::R(radius)], &W10);
        }
        WallShape::Cylinder { radius, length } => {
            names(o, &["radcyl", "lencyl"], &W10);
            let len = if length.is_finite() { length } else { 0.0 };
            card(o, &[F::R(radius), F::R(len)], &W10);
        }
    }
    if let Some(mo) = w.motion {
        names(o, &["lcid", "opt", "vx", "vy", "vz"], &W10);
        let f = [
            F::I(m.curves[mo.curve].id),
            F::I(mo.displacement as i64),
            F::R(mo.dir[0]),
            F::R(mo.dir[1]),
            F::R(mo.dir[2]),
        ];
        exact_card(o, &f);
    }
}

fn interactions(o: &mut String, m: &Model, wall_sets: &[i64]) {
    for (w, &nsid) in m.rigid_walls.iter().zip(wall_sets) {
        if w.shape != WallShape::Plane || w.motion.is_some() {
            geometric_wall(o, m, w, nsid);
            continue;
        }
        let kw = if w.extent.is_some() {
            "*RIGIDWALL_PLANAR_FINITE"
        } else {
            "*RIGIDWALL_PLANAR"
        };
        simple(o, kw, &["nsid"], &[F::I(nsid)]);
        names(o, &["xt", "yt", "zt", "xh", "yh", "zh", "fric"], &W10);
        let f = [
            w.tail[0], w.tail[1], w.tail[2], w.head[0], w.head[1], w.head[2], w.fric,
        ]
        .map(F::R);
        card(o, &f, &W10);
        if let Some(e) = w.extent {
            // the edge vector's head: tail + l (l a unit vector in the plane)
            names(o, &["xhev", "yhev", "zhev", "lenl", "lenm"], &W10);
            let hev = cleave_core::math::add(w.tail, e.l);
            let f = [hev[0], hev[1], hev[2], e.len_l, e.len_m].map(F::R);
            exact_card(o, &f);
        }
    }
    for c in &m.contacts {
        let kw = if c.single_surface {
            "*CONTACT_AUTOMATIC_SINGLE_SURFACE"
        } else if c.one_way {
            "*CONTACT_AUTOMATIC_NODES_TO_SURFACE"
        } else {
            "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"
        };
        let (sid, styp) = surface(m, Some(&c.slave));
        let (mid, mtyp) = if c.single_surface {
            (F::I(0), F::I(2))
        } else {
            surface(m, c.master.as_ref())
        };
        simple(
            o,
            kw,
            &["ssid", "msid", "sstyp", "mstyp"],
            &[sid, mid, styp, mtyp],
        );
        names(o, &["fs", "fd", "dc"], &W10);
        card(o, &[F::R(c.fs), F::R(c.fd), F::R(c.dc)], &W10);
    }
    for t in &m.tied {
        let ((sid, styp), kw) = match &t.slave {
            TiedSlave::NodeSet(k) => (
                (F::I(m.node_sets[*k].id), F::I(4)),
                "*CONTACT_TIED_NODES_TO_SURFACE",
            ),
            TiedSlave::Surface(side) => {
                (surface(m, Some(side)), "*CONTACT_TIED_SURFACE_TO_SURFACE")
            }
        };
        let (mid, mtyp) = surface(m, Some(&t.master));
        simple(
            o,
            kw,
            &["ssid", "msid", "sstyp", "mstyp"],
            &[sid, mid, styp, mtyp],
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_fit_and_keep_precision() {
        for &v in &[
            0.0,
            1.0,
            -1.0,
            0.1,
            1.0 / 3.0,
            -2.0 / 3.0 * 1e-7,
            2.1e11,
            -1.234_567_890_123e-30,
            9.87654321e250,
            123_456_789.123,
            -0.000_123_456_789,
        ] {
            for w in [10usize, 16, 20] {
                let s = fmt_f64(v, w);
                assert!(s.len() <= w, "{v} in {w}: {s}");
                let back: f64 = s.parse().unwrap();
                let rel = if v == 0.0 {
                    back.abs()
                } else {
                    ((back - v) / v).abs()
                };
                let tol = match w {
                    10 => 1e-3,
                    16 => 1e-10,
                    _ => 1e-13,
                };
                assert!(rel <= tol, "{v} in {w}: {s} ({rel})");
            }
        }
        assert_eq!(fmt_f64(2.1e11, 10), "2.1e11");
        assert_eq!(fmt_f64(0.3, 10), "0.3");
        assert_eq!(fmt_f64(0.1 + 1e-17, 15), "0.1");
        assert_eq!(fmt_f64(-1.0 / 3.0, 15), "-0.333333333333");
    }
}
