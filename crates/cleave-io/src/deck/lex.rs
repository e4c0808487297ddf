//! Splitting a keyword deck into keyword blocks and their data lines.
//!
//! Rules (LS-DYNA keyword manual, "General card format"): a line starting with `$` is a
//! comment; a line starting with `*` starts a keyword (case-insensitive; anything after the
//! first blank, such as the memory size on `*KEYWORD 100m`, is ignored); every other line is a
//! data card of the current keyword; `*END` ends the deck and what follows it is ignored.
//! CRLF line endings and trailing whitespace are accepted. Blank lines at the end of a block
//! are dropped; blank lines inside a block are kept (a blank card means "all defaults").
//!
//! The fixed-format layout ([`Format`]): `LONG=Y` or `I10=Y` on a file's `*KEYWORD` line sets
//! it for the blocks after it (`LONG=S`, `LONG=N`, `LONG=K` and `I10=N` set the standard one);
//! a keyword's name ending in `+` (long), `%` (I10) or `-` (standard), or followed by that sign
//! alone (`*NODE +`), sets it for that keyword. A block with neither takes the layout of the
//! file that includes its file (the deck's: standard).

use std::rc::Rc;

use super::error::DeckError;
use super::fields::Format;

/// One data line of a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Line<'a> {
    /// 1-based line number in the file.
    pub no: usize,
    /// The text, without line ending and trailing whitespace.
    pub text: &'a str,
}

impl Line<'_> {
    pub fn is_blank(&self) -> bool {
        self.text.trim().is_empty()
    }
}

/// A keyword and its data lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block<'a> {
    /// The file the block is in (the deck, or a file it includes).
    pub file: Rc<str>,
    /// Upper-case keyword with its leading `*`, e.g. `*MAT_ELASTIC_TITLE`.
    pub keyword: String,
    /// Line of the keyword.
    pub line: usize,
    pub lines: Vec<Line<'a>>,
    /// 0 for the deck and its plain includes; k > 0 for the blocks read through the k-th
    /// `*INCLUDE_TRANSFORM` (and, on that `*INCLUDE_TRANSFORM` block itself, the group it
    /// opens), whose ids are offset and nodes moved as it says.
    pub group: usize,
    /// The layout of its fixed-format cards: set by the keyword's sign or its file's
    /// `*KEYWORD` line; `None` until the includes are resolved when neither says.
    pub format: Option<Format>,
}

/// A keyword's name without a layout sign, and the layout the sign asks for: `*NODE+` and
/// `*NODE +` are `*NODE` in the long layout.
fn name_and_sign(rest: &str) -> (&str, Option<Format>) {
    let name = rest
        .split(|c: char| c.is_whitespace() || c == ',')
        .next()
        .unwrap_or("");
    let sign = |c: char| match c {
        '+' => Some(Format::Long),
        '%' => Some(Format::I10),
        '-' => Some(Format::Standard),
        _ => None,
    };
    if let Some(f) = name.chars().last().and_then(sign) {
        if name.len() > 1 {
            return (&name[..name.len() - 1], Some(f));
        }
    }
    let after = rest[name.len()..].trim();
    let alone = (after.len() == 1).then(|| after.chars().next().and_then(sign));
    (name, alone.flatten())
}

/// The layout a `*KEYWORD` line's options set (`None`: they say nothing of it). An unknown
/// value of `LONG` or `I10` is an error.
fn keyword_options(rest: &str) -> Result<Option<Format>, String> {
    let mut format = None;
    let mut long = false;
    // `LONG = Y` as `LONG=Y`
    let mut joined = rest.to_string();
    for (a, b) in [(" =", "="), ("= ", "="), ("\t=", "="), ("=\t", "=")] {
        while joined.contains(a) {
            joined = joined.replace(a, b);
        }
    }
    for opt in joined.split(|c: char| c.is_whitespace() || c == ',') {
        let Some((key, value)) = opt.split_once('=') else {
            continue;
        };
        let value = value.trim().to_ascii_uppercase();
        match key.trim().to_ascii_uppercase().as_str() {
            "LONG" => match value.as_str() {
                "Y" => {
                    format = Some(Format::Long);
                    long = true;
                }
                "S" | "N" | "K" => format = Some(Format::Standard),
                v => return Err(format!("LONG={v}: cleave reads LONG=Y (the long layout) and LONG=S, N or K (the standard one)")),
            },
            "I10" => match value.as_str() {
                "Y" if !long => format = Some(Format::I10),
                "Y" => {}
                "N" if !long => format = Some(Format::Standard),
                "N" => {}
                v => return Err(format!("I10={v}: cleave reads I10=Y and I10=N")),
            },
            _ => {}
        }
    }
    Ok(format)
}

/// Splits `text` into blocks. Errors: data before the first keyword.
pub fn lex<'a>(text: &'a str, file: &str) -> Result<Vec<Block<'a>>, DeckError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let file_rc: Rc<str> = Rc::from(file);
    let mut blocks: Vec<Block<'a>> = Vec::new();
    let mut file_format = None;
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let line = raw.trim_end();
        let start = line.trim_start();
        if start.starts_with('$') {
            continue;
        }
        if let Some(rest) = start.strip_prefix('*') {
            let (name, sign) = name_and_sign(rest);
            let keyword = format!("*{}", name.to_ascii_uppercase());
            if keyword == "*END" {
                break;
            }
            if keyword == "*KEYWORD" {
                if let Some(f) = keyword_options(&rest[name.len()..])
                    .map_err(|m| DeckError::at(file, no, Some("*KEYWORD"), m))?
                {
                    file_format = Some(f);
                }
            }
            blocks.push(Block {
                file: file_rc.clone(),
                keyword,
                line: no,
                lines: Vec::new(),
                group: 0,
                format: sign.or(file_format),
            });
            continue;
        }
        match blocks.last_mut() {
            Some(b) => b.lines.push(Line { no, text: line }),
            None if start.is_empty() => {}
            None => {
                return Err(DeckError::at(
                    file,
                    no,
                    None,
                    "data line before the first keyword (a deck starts with *KEYWORD)",
                ))
            }
        }
    }
    for b in &mut blocks {
        while b.lines.last().is_some_and(|l| l.is_blank()) {
            b.lines.pop();
        }
    }
    Ok(blocks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_comments_crlf_and_end() {
        let t = "$ head\r\n*keyword 100m\r\n*Node\r\n$ c\r\n1 2  \r\n\r\n*END\r\n*JUNK\n";
        let b = lex(t, "f").unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(b[0].keyword, "*KEYWORD");
        assert_eq!(b[1].keyword, "*NODE");
        assert_eq!(b[1].line, 3);
        assert_eq!(b[1].lines, vec![Line { no: 5, text: "1 2" }]);
    }

    #[test]
    fn layout_signs_and_keyword_options() {
        assert_eq!(
            lex("*KEYWORD LONG = Y\n", "f").unwrap()[0].format,
            Some(Format::Long)
        );
        let t = "*KEYWORD 100m LONG=Y\n*NODE+\n*ELEMENT_SOLID %\n*PART-\n\
                 *ELEMENT_SOLID (ten nodes format)\n*MAT_MOONEY-RIVLIN_RUBBER\n";
        let b = lex(t, "f").unwrap();
        let got: Vec<(&str, Option<Format>)> =
            b.iter().map(|b| (b.keyword.as_str(), b.format)).collect();
        use Format::*;
        assert_eq!(
            got,
            vec![
                ("*KEYWORD", Some(Long)),
                ("*NODE", Some(Long)),
                ("*ELEMENT_SOLID", Some(I10)),
                ("*PART", Some(Standard)),
                ("*ELEMENT_SOLID", Some(Long)),
                ("*MAT_MOONEY-RIVLIN_RUBBER", Some(Long)),
            ]
        );
        // no option: no layout until the includes say
        assert_eq!(lex("*KEYWORD\n*NODE\n", "f").unwrap()[1].format, None);
        let e = lex("*KEYWORD LONG=1\n", "f").unwrap_err();
        assert_eq!(e.line, Some(1));
    }

    #[test]
    fn data_before_keyword_is_an_error() {
        let e = lex("\n1, 2\n*KEYWORD\n", "f").unwrap_err();
        assert_eq!(e.line, Some(2));
    }
}
