//! `*MAT_JOHNSON_COOK` (`*MAT_015`) and `*MAT_SIMPLIFIED_JOHNSON_COOK` (`*MAT_098`) (LS-DYNA
//! Keyword Manual, Vol. II), read into [`JohnsonCook`]. What cleave does not model is an
//! error, not a silent change of the physics: the other rate forms (RATEOP), a spall pressure
//! cutoff. Johnson-Cook damage (D1-D5), `*MAT_098` PSFAIL and `*MAT_010` FS erode the element
//! ([`cleave_core::erosion`]). VP may be 0 or 1: the rate is always the plastic one (VP 1,
//! [`JohnsonCook`]).

use cleave_core::erosion::{ErosionRule, JcDamage};
use cleave_core::material::JohnsonCook;
use cleave_core::model::MaterialKind;

use super::control::{non_negative, unsupported, warn_ignored};
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawErosion, RawMaterial};

/// A cap whose blank or 0 means none.
fn cap(c: &Card<'_>, i: usize, name: &str) -> Result<f64, DeckError> {
    let v = c.f64_nz(i, name, f64::INFINITY)?;
    if v <= 0.0 {
        return Err(c.field_err(name, format!("{v} must be positive (blank: no limit)")));
    }
    Ok(v)
}

/// A B N C at fields 0..4 and EPSO at `eps0_at`: A > 0, B >= 0, N > 0 when B > 0, C >= 0,
/// EPSO > 0 when C > 0 (the rate the flow stress is referred to, in the deck's 1/time).
fn hardening_and_rate(c: &Card<'_>, eps0_at: usize) -> Result<[f64; 5], DeckError> {
    let a = c.positive(0, "A")?;
    let b = non_negative(c, 1, "B")?;
    let n = non_negative(c, 2, "N")?;
    if b > 0.0 && n == 0.0 {
        return Err(c.field_err("N", "must be positive when B is"));
    }
    let rate = non_negative(c, 3, "C")?;
    let eps0 = c.f64_or(eps0_at, "EPSO", 0.0)?;
    if rate > 0.0 && eps0 <= 0.0 {
        return Err(c.field_err(
            "EPSO",
            format!("{eps0}: the threshold strain rate must be positive when C is"),
        ));
    }
    Ok([a, b, n, rate, if eps0 > 0.0 { eps0 } else { 1.0 }])
}

/// The material `mid` with density, Young's modulus and Poisson's ratio `m`.
fn push(
    r: &Reader<'_>,
    deck: &mut RawDeck,
    c: &Card<'_>,
    mid: i64,
    m: [f64; 3],
    jc: JohnsonCook,
    shear_only: Option<f64>,
) {
    deck.materials.push(RawMaterial {
        src: r.src(c.line),
        id: mid,
        density: m[0],
        young: m[1],
        poisson: m[2],
        kind: MaterialKind::JohnsonCook(jc),
        shear_only,
    });
}

/// `*MAT_SIMPLIFIED_JOHNSON_COOK` / `*MAT_098`: card 1 `MID RO E PR VP` (the shell fields
/// EPPFR, LCDM, NUMINT after it are ignored with a warning), card 2
/// `A B N C PSFAIL SIGMAX SIGSAT EPSO`. No thermal softening. PSFAIL: the element erodes at
/// that effective plastic strain ([`cleave_core::erosion`]); blank, 0 or 1e16 and more (LS-DYNA's
/// default 1e17): no failure. SIGMAX and SIGSAT blank or 0: no cap; VP 0 or 1.
pub fn simplified(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR VP")?;
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let e = c.positive(2, "E")?;
    let pr = poisson(&c, 3)?;
    c.code(4, "VP", 0, 0, 1)?;
    for (i, name) in [(5, "EPPFR"), (6, "LCDM"), (7, "NUMINT")] {
        warn_ignored(&c, i, name, "shell elements only", deck)?;
    }
    let c2 = r.required(W10, "A B N C PSFAIL SIGMAX SIGSAT EPSO")?;
    let [a, b, n, rate, eps0] = hardening_and_rate(&c2, 7)?;
    let psfail = c2.f64_or(4, "PSFAIL", 0.0)?;
    if psfail < 0.0 {
        return Err(c2.field_err("PSFAIL", format!("{psfail} must not be negative")));
    }
    if psfail > 0.0 && psfail < 1e16 {
        // the element erodes at this effective plastic strain
        super::erosion::plastic_strain(r, deck, &c2, mid, psfail);
    }
    let jc = JohnsonCook {
        a,
        b,
        n,
        c: rate,
        eps0,
        m: 1.0,
        t_melt: f64::INFINITY,
        t_room: 0.0,
        rho_cp: f64::INFINITY,
        sig_max: cap(&c2, 5, "SIGMAX")?,
        sig_sat: cap(&c2, 6, "SIGSAT")?,
        eos: None,
    };
    push(r, deck, &c, mid, [ro, e, pr], jc, None);
    Ok(())
}

/// Poisson's ratio at field `i`, in (-1, 0.5).
fn poisson(c: &Card<'_>, i: usize) -> Result<f64, DeckError> {
    let pr = c.f64_or(i, "PR", 0.0)?;
    if !(pr > -1.0 && pr < 0.5) {
        return Err(c.field_err("PR", format!("{pr} must lie in (-1, 0.5)")));
    }
    Ok(pr)
}

/// `*MAT_JOHNSON_COOK` / `*MAT_015`: card 1 `MID RO G E PR DTF VP RATEOP`, card 2
/// `A B N C M TM TR EPSO`, card 3 `CP PC SPALL IT D1 D2 D3 D4`, optional card 4
/// `D5 C2/P EROD EFMIN NUMINT`.
///
/// - Elasticity: with an `*EOS` on the part (its EOSID), the pressure comes from it and the
///   bulk modulus of the wave speed from its reference slope (`build/eos.rs`); PR and E may
///   then be blank. Without one the bulk response is linear and comes from G and PR
///   (E = 2 G (1 + PR)); E may be given instead of PR (PR = E / (2 G) - 1); given both, they
///   must agree with G to 1e-3.
/// - Thermal softening when TM > TR (M blank or 0: 1); the temperature rises adiabatically
///   by the plastic work over RO CP (CP blank or 0: no heating, T stays TR).
/// - Damage D1..D5 with EFMIN (blank: 1e-6): the element erodes when the Johnson-Cook damage
///   reaches 1 ([`cleave_core::erosion::JcDamage`]); EROD 1 turns erosion off.
/// - Not modelled (errors when set): RATEOP other than 0, the spall cutoff PC. DTF, IT, C2/P,
///   NUMINT are ignored with a warning when set (cleave's return always iterates, IT 1).
pub fn johnson_cook(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO G E PR DTF VP RATEOP")?;
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let g = c.positive(2, "G")?;
    let e = c.f64_or(3, "E", 0.0)?;
    let pr_given = c.opt_f64(4, "PR")?.filter(|&v| v != 0.0);
    let pr = match (e > 0.0, pr_given) {
        (_, Some(_)) => poisson(&c, 4)?,
        (true, None) => {
            let pr = e / (2.0 * g) - 1.0;
            if !(pr > -1.0 && pr < 0.5) {
                return Err(c.field_err(
                    "E",
                    format!("{e} with G = {g} gives Poisson's ratio {pr}, outside (-1, 0.5)"),
                ));
            }
            pr
        }
        // the bulk modulus must come from the part's *EOS (checked when the parts are built)
        (false, None) => f64::NAN,
    };
    let from_g = 2.0 * g * (1.0 + pr);
    if e > 0.0 && !pr.is_nan() && (e - from_g).abs() > 1e-3 * from_g {
        return Err(c.field_err(
            "E",
            format!("{e} disagrees with G = {g} and PR = {pr} (2 G (1 + PR) = {from_g})"),
        ));
    }
    let young = if e > 0.0 { e } else { from_g };
    warn_ignored(&c, 5, "DTF", "erosion by time step is not modelled", deck)?;
    c.code(6, "VP", 0, 0, 1)?;
    unsupported(
        &c,
        7,
        "RATEOP",
        "a rate form other than Johnson-Cook's (RATEOP 0)",
    )?;

    let c2 = r.required(W10, "A B N C M TM TR EPSO")?;
    let [a, b, n, rate, eps0] = hardening_and_rate(&c2, 7)?;
    let m = c2.f64_nz(4, "M", 1.0)?;
    if m <= 0.0 {
        return Err(c2.field_err("M", format!("{m} must be positive")));
    }
    let tm = c2.f64_or(5, "TM", 0.0)?;
    let tr = c2.f64_or(6, "TR", 0.0)?;
    let t_melt = if tm == 0.0 {
        f64::INFINITY
    } else if tm > tr {
        tm
    } else {
        return Err(c2.field_err("TM", format!("{tm} must exceed TR = {tr}")));
    };

    let c3 = r.required(W10, "CP PC SPALL IT D1 D2 D3 D4")?;
    let cp = non_negative(&c3, 0, "CP")?;
    unsupported(&c3, 1, "PC", "a spall pressure cutoff")?;
    warn_ignored(&c3, 2, "SPALL", "no spall model", deck)?;
    warn_ignored(&c3, 3, "IT", "the return always iterates", deck)?;
    let mut d = [0.0; 5];
    for (i, name) in [(4, "D1"), (5, "D2"), (6, "D3"), (7, "D4")] {
        d[i - 4] = c3.f64_or(i, name, 0.0)?;
    }
    let (mut erod, mut efmin) = (0, 1e-6);
    if let Some(c4) = r.next(W10)? {
        d[4] = c4.f64_or(0, "D5", 0.0)?;
        warn_ignored(&c4, 1, "C2/P", "the rate form of RATEOP 0 is used", deck)?;
        erod = c4.code(2, "EROD", 0, 0, 1)?;
        efmin = c4.f64_nz(3, "EFMIN", 1e-6)?;
        if efmin < 0.0 {
            return Err(c4.field_err("EFMIN", format!("{efmin} must not be negative")));
        }
        warn_ignored(&c4, 4, "NUMINT", "a solid element has one point", deck)?;
    }
    if d.iter().any(|&v| v != 0.0) && erod == 0 {
        // Johnson-Cook damage: the element erodes when it reaches 1
        deck.erosions.push(RawErosion {
            src: r.src(c3.line),
            mid,
            rule: ErosionRule {
                johnson_cook: Some(JcDamage { d, efmin }),
                ..Default::default()
            },
            from_material: true,
        });
    }
    let jc = JohnsonCook {
        a,
        b,
        n,
        c: rate,
        eps0,
        m,
        t_melt,
        t_room: tr,
        rho_cp: if cp > 0.0 { ro * cp } else { f64::INFINITY },
        sig_max: f64::INFINITY,
        sig_sat: f64::INFINITY,
        eos: None,
    };
    let shear_only = pr.is_nan().then_some(g);
    push(r, deck, &c, mid, [ro, young, pr], jc, shear_only);
    Ok(())
}

/// `*MAT_ELASTIC_PLASTIC_HYDRO` / `*MAT_010`: card 1 `MID RO G SIGY EH PC FS CHARL`, optional
/// card 2 `A1 A2 SPALL`, optional cards 3-6 `EPS1..EPS16`, `ES1..ES16`. An elastic-plastic
/// deviator with linear hardening, yield stress `SIGY + EH ep`, and the pressure of the part's
/// equation of state (EOSID, required: the bulk modulus comes from it). cleave runs it as a
/// Johnson-Cook material with A = SIGY, B = EH, N = 1 and no rate or temperature terms (the
/// same deviatoric return and EOS update). PC blank or 0 means no cutoff, as in LS-DYNA;
/// FS > 0 erodes the element at that effective plastic strain ([`cleave_core::erosion`]);
/// another PC (a pressure cutoff), A1 and A2 (a pressure-dependent yield stress) and the EPS/ES
/// curve are errors; CHARL and SPALL warn.
pub fn elastic_plastic_hydro(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO G SIGY EH PC FS CHARL")?;
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let g = c.positive(2, "G")?;
    let sigy = c.positive(3, "SIGY")?;
    let eh = non_negative(&c, 4, "EH")?;
    unsupported(&c, 5, "PC", "a pressure cutoff")?;
    let fs = non_negative(&c, 6, "FS")?;
    if fs > 0.0 {
        // the element erodes at this effective plastic strain
        super::erosion::plastic_strain(r, deck, &c, mid, fs);
    }
    warn_ignored(&c, 7, "CHARL", "no erosion by characteristic length", deck)?;
    if let Some(c2) = r.next(W10)? {
        unsupported(&c2, 0, "A1", "a pressure-dependent yield stress")?;
        unsupported(&c2, 1, "A2", "a pressure-dependent yield stress")?;
        warn_ignored(&c2, 2, "SPALL", "no spall model", deck)?;
    }
    for k in 0..4 {
        let Some(ck) = r.next(W10)? else { break };
        let name = if k < 2 { "EPS" } else { "ES" };
        for i in 0..8 {
            unsupported(
                &ck,
                i,
                name,
                "a piecewise hardening curve on *MAT_010 (use EH, or *MAT_024)",
            )?;
        }
    }
    let jc = JohnsonCook {
        a: sigy,
        b: eh,
        n: 1.0,
        c: 0.0,
        eps0: 1.0,
        m: 1.0,
        t_melt: f64::INFINITY,
        t_room: 0.0,
        rho_cp: f64::INFINITY,
        sig_max: f64::INFINITY,
        sig_sat: f64::INFINITY,
        eos: None,
    };
    // E and PR follow from G and the EOS's bulk modulus when the parts are built
    push(r, deck, &c, mid, [ro, 3.0 * g, f64::NAN], jc, Some(g));
    Ok(())
}
