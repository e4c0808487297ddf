//! Decoding one data card into fields, and fields into numbers.
//!
//! A card containing a comma is free format (comma-separated; a blank field takes the default).
//! Otherwise it is fixed format: consecutive fields of the widths the LS-DYNA keyword manual
//! gives for that card (10 characters in general). Numbers may use Fortran exponents
//! (`1.0d-3`, `1.0D+3`); NaN and infinities are rejected.
//!
//! Three fixed-format layouts ([`Format`]): standard (the manual's widths), I10 (every field
//! under 10 characters widened to 10) and long (every field under 20 widened to 20; the
//! 20-column ones, such as `*DEFINE_CURVE`'s points, kept; 80-column titles and file names
//! doubled to 160), chosen for a whole file by `*KEYWORD I10=Y` or `*KEYWORD LONG=Y` and for
//! one keyword by the suffix `%`, `+` (or `-`, standard) written after its name, as LS-DYNA
//! (since 971 R7.1 and R9) reads them and PRIMER's manual and PyDyna's writer lay them out.

use std::borrow::Cow;

use super::error::DeckError;
use super::lex::Line;
use super::params::Params;

/// 8 fields of 10 characters: the general LS-DYNA card.
pub const W10: &[usize] = &[10; 8];

/// The fixed-format layout of a keyword's cards.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Format {
    /// The widths of the keyword manual (8, 10, 16, ... characters).
    #[default]
    Standard,
    /// `I10=Y` / `%`: fields narrower than 10 characters are 10 wide (ids up to 10 digits).
    I10,
    /// `LONG=Y` / `+`: fields narrower than 20 characters are 20 wide; 80-column text
    /// (titles, file names) 160; the others keep their width.
    Long,
}

impl Format {
    /// The field widths of a card whose standard widths are `widths`.
    pub fn widths(self, widths: &'static [usize]) -> Cow<'static, [usize]> {
        match self {
            Format::Standard => Cow::Borrowed(widths),
            Format::I10 => Cow::Owned(widths.iter().map(|&w| w.max(10)).collect()),
            Format::Long => Cow::Owned(
                widths
                    .iter()
                    .map(|&w| match w {
                        0..=19 => 20,
                        80.. => 2 * w,
                        _ => w,
                    })
                    .collect(),
            ),
        }
    }

    /// The columns taken by the first `n` fields of a card whose standard widths are `widths`.
    pub fn columns(self, widths: &'static [usize], n: usize) -> usize {
        self.widths(widths).iter().take(n).sum()
    }
}

/// A data card split into fields, with what is needed to report an error.
#[derive(Clone, Debug)]
pub struct Card<'a> {
    pub file: &'a str,
    pub keyword: &'a str,
    pub line: usize,
    /// Whether the card was comma-separated.
    pub free: bool,
    fields: Vec<Cow<'a, str>>,
    /// Fixed format: bit i set when field i's text runs on into field i + 1 (no blank on
    /// either side of the column between them), to explain a value that does not parse.
    joined: u64,
    /// The fields' widths (fixed format), in the card's [`Format`].
    widths: Cow<'static, [usize]>,
}

impl<'a> Card<'a> {
    /// Splits `line` by the card's field `widths` (fixed format, standard layout) or by commas
    /// (free format). Free format with more non-blank fields than the card has is an error.
    pub fn new(
        file: &'a str,
        keyword: &'a str,
        line: Line<'a>,
        widths: &'static [usize],
    ) -> Result<Self, DeckError> {
        Self::in_format(file, keyword, line, widths, Format::Standard)
    }

    /// As [`Card::new`], the fixed fields laid out in `format` (the standard `widths` widened).
    pub fn in_format(
        file: &'a str,
        keyword: &'a str,
        line: Line<'a>,
        widths: &'static [usize],
        format: Format,
    ) -> Result<Self, DeckError> {
        let widths = format.widths(widths);
        let free = line.text.contains(',');
        let width: usize = widths.iter().sum();
        if !free && !blank_beyond(line.text, width) {
            return Err(DeckError::at(
                file,
                line.no,
                Some(keyword),
                format!("text beyond column {width}, the end of this card's fixed-format fields (widths {:?}{}); check the column layout or use commas", widths.as_ref(), match format {
                    Format::Standard => "",
                    Format::I10 => ", the I10 layout",
                    Format::Long => ", the long layout",
                }),
            ));
        }
        let fields: Vec<Cow<'a, str>> = if free {
            line.text
                .split(',')
                .map(|f| Cow::Borrowed(f.trim()))
                .collect()
        } else {
            split_fixed(line.text, &widths)
                .into_iter()
                .map(Cow::Borrowed)
                .collect()
        };
        let mut joined = 0u64;
        if !free {
            let chars: Vec<char> = line.text.chars().collect();
            let mut col = 0;
            for (i, &w) in widths.iter().enumerate().take(63) {
                col += w;
                let at = |k: usize| chars.get(k).is_some_and(|c| !c.is_whitespace());
                if col > 0 && at(col - 1) && at(col) {
                    joined |= 1 << i;
                }
            }
        }
        let card = Card {
            file,
            keyword,
            line: line.no,
            free,
            fields,
            joined,
            widths,
        };
        if free {
            let n = card.count();
            let fields = card.widths.len();
            if n > fields {
                return Err(card.err(format!("too many fields: {n} (this card has {fields})")));
            }
        }
        Ok(card)
    }

    /// Number of fields up to the last non-blank one.
    pub fn count(&self) -> usize {
        self.fields
            .iter()
            .rposition(|f| !f.is_empty())
            .map_or(0, |i| i + 1)
    }

    /// The trimmed text of field `i` (empty if blank or absent).
    pub fn raw(&self, i: usize) -> &str {
        self.fields.get(i).map_or("", |f| f.as_ref())
    }

    /// Puts each `&name` or `-&name` field's parameter value in its place (`*PARAMETER`);
    /// an undefined name is an error naming it and the field's position.
    pub fn substitute(mut self, params: &Params) -> Result<Self, DeckError> {
        for k in 0..self.fields.len() {
            let f = self.fields[k].as_ref();
            let (neg, name) = match f.strip_prefix("-&") {
                Some(n) => (true, n),
                None => match f.strip_prefix('&') {
                    Some(n) => (false, n),
                    None => continue,
                },
            };
            let text = params
                .text(self.file, name, neg)
                .map_err(|m| self.err(format!("field {}: {m}", k + 1)))?;
            self.fields[k] = Cow::Owned(text);
        }
        Ok(self)
    }

    /// A parse error of field `i`, with the likely cause when the text runs on across a
    /// field's edge (a value wider than its field, or a card laid out in other widths).
    fn explain(&self, i: usize, m: String) -> String {
        let into_next = i < 63 && self.joined & (1 << i) != 0;
        let from_prev = i > 0 && i <= 63 && self.joined & (1 << (i - 1)) != 0;
        if !(into_next || from_prev) {
            return m;
        }
        let start: usize = self.widths[..i.min(self.widths.len())].iter().sum();
        let w = self.widths.get(i).copied().unwrap_or(0);
        format!(
            "{m}: the text runs across the edge of this field (columns {}-{}): fixed-format fields here are {w} characters wide; align the values to them or separate them with commas",
            start + 1,
            start + w
        )
    }

    /// An error at this card's line.
    pub fn err(&self, message: impl Into<String>) -> DeckError {
        DeckError::at(self.file, self.line, Some(self.keyword), message)
    }

    /// An error at this card's line naming a field.
    pub fn field_err(&self, field: &str, message: impl Into<String>) -> DeckError {
        self.err(message).with_field(field)
    }

    /// A real field; `None` if blank.
    pub fn opt_f64(&self, i: usize, name: &str) -> Result<Option<f64>, DeckError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        parse_f64(s)
            .map(Some)
            .map_err(|m| self.field_err(name, self.explain(i, m)))
    }

    /// A real field; `default` if blank.
    pub fn f64_or(&self, i: usize, name: &str, default: f64) -> Result<f64, DeckError> {
        Ok(self.opt_f64(i, name)?.unwrap_or(default))
    }

    /// A real field whose blank or zero value means `default` (LS-DYNA's rule for scale
    /// factors and most control parameters, as a blank fixed field reads as 0).
    pub fn f64_nz(&self, i: usize, name: &str, default: f64) -> Result<f64, DeckError> {
        let v = self.f64_or(i, name, 0.0)?;
        Ok(if v == 0.0 { default } else { v })
    }

    /// An integer field; `None` if blank. A real with a fraction is an error.
    pub fn opt_i64(&self, i: usize, name: &str) -> Result<Option<i64>, DeckError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        parse_i64(s)
            .map(Some)
            .map_err(|m| self.field_err(name, self.explain(i, m)))
    }

    /// An integer field; `default` if blank.
    pub fn i64_or(&self, i: usize, name: &str, default: i64) -> Result<i64, DeckError> {
        Ok(self.opt_i64(i, name)?.unwrap_or(default))
    }

    /// An integer code field that must lie in `lo..=hi` (blank: `default`).
    pub fn code(
        &self,
        i: usize,
        name: &str,
        default: i64,
        lo: i64,
        hi: i64,
    ) -> Result<i32, DeckError> {
        let v = self.i64_or(i, name, default)?;
        if v < lo || v > hi {
            return Err(self.field_err(name, format!("{v} is not one of {lo}..{hi}")));
        }
        Ok(v as i32)
    }

    /// A required id: present and positive.
    pub fn id(&self, i: usize, name: &str) -> Result<i64, DeckError> {
        match self.opt_i64(i, name)? {
            None => Err(self.field_err(name, "missing (a positive id is required)")),
            Some(v) if v <= 0 => Err(self.field_err(name, format!("{v} is not a positive id"))),
            Some(v) => Ok(v),
        }
    }

    /// An optional reference id: blank or 0 means none; negative is an error.
    pub fn ref_id(&self, i: usize, name: &str) -> Result<Option<i64>, DeckError> {
        match self.i64_or(i, name, 0)? {
            0 => Ok(None),
            v if v < 0 => Err(self.field_err(name, format!("{v} is not a valid id"))),
            v => Ok(Some(v)),
        }
    }

    /// A real field that must be positive.
    pub fn positive(&self, i: usize, name: &str) -> Result<f64, DeckError> {
        match self.opt_f64(i, name)? {
            None => Err(self.field_err(name, "missing (must be positive)")),
            Some(v) if v <= 0.0 => Err(self.field_err(name, format!("{v} must be positive"))),
            Some(v) => Ok(v),
        }
    }
}

/// Splits a fixed-format line into fields of the given widths (counted in characters; what
/// lies beyond the last field is ignored, as LS-DYNA reads only the card's columns).
pub fn split_fixed<'a>(text: &'a str, widths: &[usize]) -> Vec<&'a str> {
    let mut out = Vec::with_capacity(widths.len());
    let mut rest = text;
    for &w in widths {
        let end = rest.char_indices().nth(w).map_or(rest.len(), |(b, _)| b);
        out.push(rest[..end].trim());
        rest = &rest[end..];
    }
    out
}

/// Whether a fixed-format line has anything beyond its first `n` characters.
pub fn blank_beyond(text: &str, n: usize) -> bool {
    text.chars().skip(n).all(char::is_whitespace)
}

/// Parses a real number: plain decimal, `e`/`E` or Fortran `d`/`D` exponent. Finite only.
pub fn parse_f64(s: &str) -> Result<f64, String> {
    let ok = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | 'e' | 'E' | 'd' | 'D'))
        && s.chars().any(|c| c.is_ascii_digit());
    let v = if ok {
        s.replace(['d', 'D'], "e").parse::<f64>().ok()
    } else {
        None
    };
    match v {
        Some(v) if v.is_finite() => Ok(v),
        Some(_) => Err(format!("'{}' is out of range", show(s))),
        None if s.contains('\t') => Err(format!(
            "'{}' is not a number (tab characters are not allowed in fixed-format cards; use spaces or commas)",
            show(s)
        )),
        None => Err(format!("'{}' is not a number", show(s))),
    }
}

/// Parses an integer; a real with a zero fraction (`3.`, `3.0`) is accepted.
pub fn parse_i64(s: &str) -> Result<i64, String> {
    if let Ok(v) = s.strip_prefix('+').unwrap_or(s).parse::<i64>() {
        return Ok(v);
    }
    let v = parse_f64(s)?;
    if v.fract() != 0.0 {
        return Err(format!("'{}' is not an integer", show(s)));
    }
    if v.abs() > 9.0e15 {
        return Err(format!("'{}' is out of range", show(s)));
    }
    Ok(v as i64)
}

/// A field's text for a message: control characters escaped, at most 40 characters.
pub(crate) fn show(s: &str) -> String {
    let mut out: String = s.chars().take(40).flat_map(char::escape_debug).collect();
    if s.chars().count() > 40 {
        out.push_str("...");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_f64("1.0d-3"), Ok(1.0e-3));
        assert_eq!(parse_f64("1.0D+3"), Ok(1.0e3));
        assert_eq!(parse_f64("2.5e9"), Ok(2.5e9));
        assert_eq!(parse_f64("1e+09"), Ok(1e9));
        assert_eq!(parse_f64("7"), Ok(7.0));
        assert_eq!(parse_f64("-.5"), Ok(-0.5));
        assert!(parse_f64("NaN").is_err());
        assert!(parse_f64("inf").is_err());
        assert!(parse_f64("1e999").is_err());
        assert!(parse_f64("abc").is_err());
        assert!(parse_f64("e").is_err());
        assert_eq!(parse_i64("12"), Ok(12));
        assert_eq!(parse_i64("+12"), Ok(12));
        assert_eq!(parse_i64("3."), Ok(3));
        assert_eq!(parse_i64("1.5"), Err("'1.5' is not an integer".into()));
    }

    #[test]
    fn fixed_and_free_split() {
        let l = Line {
            no: 3,
            text: "       1     0.5           2",
        };
        let c = Card::new("f", "*X", l, &[8, 10, 10]).unwrap();
        assert!(!c.free);
        assert_eq!(
            (c.raw(0), c.raw(1), c.raw(2), c.raw(3)),
            ("1", "0.5", "2", "")
        );
        let l = Line {
            no: 3,
            text: "1,,2,",
        };
        let c = Card::new("f", "*X", l, &[8, 10, 10]).unwrap();
        assert!(c.free);
        assert_eq!(c.count(), 3);
        assert_eq!(c.f64_or(1, "B", 4.0).unwrap(), 4.0);
        let l = Line {
            no: 3,
            text: "1,2,3,4",
        };
        assert!(Card::new("f", "*X", l, &[8, 10, 10]).is_err());
    }

    #[test]
    fn multibyte_text_does_not_panic() {
        let v = split_fixed("é€😀abcdefghijklmnop", &[2, 3, 10]);
        assert_eq!(v[0], "é€");
    }
}
