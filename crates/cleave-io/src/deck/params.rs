//! `*PARAMETER`, `*PARAMETER_LOCAL`, `*PARAMETER_EXPRESSION` and
//! `*PARAMETER_EXPRESSION_LOCAL`: named values that any numeric field may use as `&name` (or
//! `-&name`, negated), read before any other card so their place in the deck does not matter.
//!
//! - `*PARAMETER`: up to four pairs `PRMR VAL` per card (fields of 10). PRMR is a type letter,
//!   `R` real, `I` integer or `C` text, then the name (`R rho` or `Rrho`); VAL is read as that
//!   type.
//! - `*PARAMETER_EXPRESSION`: `PRMR EXPRESSION` (fields of 10 and 70; in free format the
//!   first comma ends PRMR), evaluated in deck order, so an expression uses the parameters
//!   defined above it ([`super::expr`]). An integer expression must come out whole.
//! - `_LOCAL`: the name holds only in the file it is defined in (an included file), and there
//!   it hides a global one of the same name.
//! - Names are case-insensitive. Defining a name twice in one scope is an error naming both
//!   lines, unless the deck says which definition holds with `*PARAMETER_DUPLICATION` DFLAG:
//!   1 or 3 keep the first (LS-DYNA warns with 1), 2 or 4 the last. (Without that card LS-DYNA
//!   keeps the first with a warning; cleave asks the deck to say so rather than guess.)

use std::collections::HashMap;

use super::error::DeckError;
use super::expr;
use super::fields::{parse_f64, parse_i64, Card, Format, W10};
use super::lex::{Block, Line};

/// A parameter's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Real(f64),
    Int(i64),
    Text(String),
}

/// The parameters of a deck, global and per file.
#[derive(Debug, Default)]
pub struct Params {
    global: HashMap<String, (Value, String)>,
    local: HashMap<(String, String), (Value, String)>,
    /// `*PARAMETER_DUPLICATION` DFLAG (0: no such card, a name defined twice is an error).
    duplication: i64,
}

impl Params {
    /// Reads every parameter keyword of `blocks`, in order.
    pub fn read(blocks: &[Block<'_>]) -> Result<Self, DeckError> {
        let mut p = Self::default();
        for b in blocks
            .iter()
            .filter(|b| b.keyword == "*PARAMETER_DUPLICATION")
        {
            if let Some(l) = b.lines.iter().find(|l| !l.is_blank()) {
                let c =
                    Card::in_format(&b.file, &b.keyword, *l, W10, b.format.unwrap_or_default())?;
                let v = c.i64_or(0, "DFLAG", 1)?;
                if !(1..=4).contains(&v) {
                    return Err(c.field_err("DFLAG", format!("{v} is not one of 1..4")));
                }
                p.duplication = v;
            } else {
                p.duplication = 1;
            }
        }
        for b in blocks {
            let local = b.keyword.ends_with("_LOCAL");
            match b.keyword.trim_end_matches("_LOCAL") {
                "*PARAMETER" => {
                    for l in b.lines.iter().filter(|l| !l.is_blank()) {
                        let c = Card::in_format(
                            &b.file,
                            &b.keyword,
                            *l,
                            W10,
                            b.format.unwrap_or_default(),
                        )?;
                        for pair in 0..4 {
                            let prmr = c.raw(2 * pair).to_string();
                            if prmr.is_empty() {
                                continue;
                            }
                            let (kind, name) = type_and_name(&prmr)
                                .map_err(|m| c.field_err(&format!("PRMR{}", pair + 1), m))?;
                            let field = format!("VAL{}", pair + 1);
                            let raw = c.raw(2 * pair + 1);
                            let value = match kind {
                                'R' => {
                                    Value::Real(parse_f64(raw).map_err(|m| c.field_err(&field, m))?)
                                }
                                'I' => {
                                    Value::Int(parse_i64(raw).map_err(|m| c.field_err(&field, m))?)
                                }
                                _ => Value::Text(raw.to_string()),
                            };
                            p.define(&c, &name, value, local)?;
                        }
                    }
                }
                "*PARAMETER_EXPRESSION" => {
                    for l in b.lines.iter().filter(|l| !l.is_blank()) {
                        // (the card only places errors: commas inside the expression are no
                        // field separators)
                        let anchor = Line { no: l.no, text: "" };
                        let c = Card::new(&b.file, &b.keyword, anchor, W10)?;
                        let (prmr, text) = split_expression(l.text, b.format.unwrap_or_default());
                        let (kind, name) =
                            type_and_name(&prmr).map_err(|m| c.field_err("PRMR", m))?;
                        let lookup = |n: &str| match p.get(&b.file, n) {
                            Some(Value::Real(v)) => Some(*v),
                            Some(Value::Int(v)) => Some(*v as f64),
                            _ => None,
                        };
                        let v =
                            expr::eval(&text, &lookup).map_err(|m| c.field_err("EXPRESSION", m))?;
                        let value = match kind {
                            'I' if v.fract() != 0.0 || v.abs() > 9.0e15 => {
                                return Err(c.field_err(
                                    "EXPRESSION",
                                    format!("the integer parameter {name} comes out as {v}"),
                                ))
                            }
                            'I' => Value::Int(v as i64),
                            'R' => Value::Real(v),
                            _ => {
                                return Err(c.field_err(
                                    "PRMR",
                                    "an expression gives a number: type R or I",
                                ))
                            }
                        };
                        p.define(&c, &name, value, local)?;
                    }
                }
                _ => {}
            }
        }
        Ok(p)
    }

    fn define(&mut self, c: &Card<'_>, name: &str, v: Value, local: bool) -> Result<(), DeckError> {
        let at = format!("{}:{}", c.file, c.line);
        let key = (c.file.to_string(), name.to_string());
        let defined = if local {
            self.local.contains_key(&key)
        } else {
            self.global.contains_key(name)
        };
        if defined && matches!(self.duplication, 1 | 3) {
            // *PARAMETER_DUPLICATION: the first definition holds
            return Ok(());
        }
        if defined && matches!(self.duplication, 2 | 4) {
            if local {
                self.local.insert(key, (v, at));
            } else {
                self.global.insert(name.to_string(), (v, at));
            }
            return Ok(());
        }
        let old = if local {
            self.local
                .insert((c.file.to_string(), name.to_string()), (v, at))
        } else {
            self.global.insert(name.to_string(), (v, at))
        };
        match old {
            Some((_, first)) => Err(c.err(format!(
                "parameter {name} is defined twice (first at {first})"
            ))),
            None => Ok(()),
        }
    }

    /// The value of `name` as seen from `file`.
    pub fn get(&self, file: &str, name: &str) -> Option<&Value> {
        let name = name.trim().to_ascii_lowercase();
        self.local
            .get(&(file.to_string(), name.clone()))
            .or_else(|| self.global.get(&name))
            .map(|(v, _)| v)
    }

    /// The text that replaces `&name` (negated for `-&name`) in a field of `file`.
    pub fn text(&self, file: &str, name: &str, negate: bool) -> Result<String, String> {
        let v = self
            .get(file, name)
            .ok_or_else(|| format!("parameter &{name} is not defined (*PARAMETER)"))?;
        Ok(match (v, negate) {
            (Value::Real(x), n) => format!("{:?}", if n { -x } else { *x }),
            (Value::Int(i), n) => (if n { -i } else { *i }).to_string(),
            (Value::Text(t), false) => t.clone(),
            (Value::Text(_), true) => {
                return Err(format!("the text parameter &{name} cannot be negated"))
            }
        })
    }
}

/// The type letter (R, I or C) and the lower-case name of a PRMR field.
fn type_and_name(prmr: &str) -> Result<(char, String), String> {
    let mut chars = prmr.trim().chars();
    let kind = chars.next().map(|c| c.to_ascii_uppercase());
    let name = chars.as_str().trim().to_ascii_lowercase();
    match kind {
        Some(k @ ('R' | 'I' | 'C')) if !name.is_empty() && !name.contains(char::is_whitespace) => {
            Ok((k, name))
        }
        _ => Err(format!(
            "'{prmr}' is not a type letter (R, I or C) followed by a name"
        )),
    }
}

/// PRMR and the expression of an expression card: split at the first comma when the card is
/// comma-separated there, else after the PRMR field (column 10; 20 in the long layout).
fn split_expression(text: &str, format: Format) -> (String, String) {
    let w = format.columns(W10, 1);
    let head: String = text.chars().take(w).collect();
    if let Some(k) = head.find(',') {
        let rest = text[k + 1..].trim().trim_end_matches(',').trim();
        return (text[..k].trim().to_string(), rest.to_string());
    }
    let rest: String = text.chars().skip(w).collect();
    (head.trim().to_string(), rest.trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::lex::lex;

    #[test]
    fn parameters_expressions_and_scopes() {
        let text = "*PARAMETER\nR rho, 7850., Iseed, 3, C name, steel\n\
                    *PARAMETER_EXPRESSION\nR twice    2*rho + seed\nI n, max(4, 7)\n\
                    *PARAMETER_LOCAL\nR rho, 1.\n";
        let b = lex(text, "a.k").unwrap();
        let p = Params::read(&b).unwrap();
        assert_eq!(p.get("b.k", "RHO"), Some(&Value::Real(7850.0)));
        assert_eq!(p.get("a.k", "rho"), Some(&Value::Real(1.0)));
        assert_eq!(p.get("b.k", "twice"), Some(&Value::Real(15703.0)));
        assert_eq!(p.get("b.k", "n"), Some(&Value::Int(7)));
        assert_eq!(p.text("b.k", "seed", true).unwrap(), "-3");
        assert_eq!(p.text("b.k", "rho", false).unwrap(), "7850.0");
        assert_eq!(p.text("b.k", "name", false).unwrap(), "steel");
        assert!(p.text("b.k", "nope", false).unwrap_err().contains("&nope"));
    }

    #[test]
    fn errors_name_field_and_first_definition() {
        let read = |t: &str| Params::read(&lex(t, "a.k").unwrap()).unwrap_err();
        let e = read("*PARAMETER\nX rho, 1.\n");
        assert_eq!(e.field.as_deref(), Some("PRMR1"));
        let e = read("*PARAMETER\nI n, 2.5\n");
        assert_eq!(e.field.as_deref(), Some("VAL1"));
        let e = read("*PARAMETER\nR a, 1.\n*PARAMETER\nR A, 2.\n");
        assert!(e.to_string().contains("first at a.k:2"), "{e}");
        assert_eq!(e.line, Some(4));
        let e = read("*PARAMETER_EXPRESSION\nI n, 5/2\n");
        assert!(e.to_string().contains("comes out as 2.5"), "{e}");
        let e = read("*PARAMETER_EXPRESSION\nR x, y + 1\n*PARAMETER\nR y, 1.\n");
        assert!(e.to_string().contains("'y' is not defined"), "{e}");
    }
}
