//! Splitting a keyword deck into keyword blocks and their data lines.
//!
//! Rules (LS-DYNA keyword manual, "General card format"): a line starting with `$` is a
//! comment; a line starting with `*` starts a keyword (case-insensitive; anything after the
//! first blank, such as the memory size on `*KEYWORD 100m`, is ignored); every other line is a
//! data card of the current keyword; `*END` ends the deck and what follows it is ignored.
//! CRLF line endings and trailing whitespace are accepted. Blank lines at the end of a block
//! are dropped; blank lines inside a block are kept (a blank card means "all defaults").

use std::rc::Rc;

use super::error::DeckError;

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
}

/// Splits `text` into blocks. Errors: data before the first keyword.
pub fn lex<'a>(text: &'a str, file: &str) -> Result<Vec<Block<'a>>, DeckError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let file_rc: Rc<str> = Rc::from(file);
    let mut blocks: Vec<Block<'a>> = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let line = raw.trim_end();
        let start = line.trim_start();
        if start.starts_with('$') {
            continue;
        }
        if let Some(rest) = start.strip_prefix('*') {
            let name = rest
                .split(|c: char| c.is_whitespace() || c == ',')
                .next()
                .unwrap_or("");
            let keyword = format!("*{}", name.to_ascii_uppercase());
            if keyword == "*END" {
                break;
            }
            blocks.push(Block {
                file: file_rc.clone(),
                keyword,
                line: no,
                lines: Vec::new(),
                group: 0,
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
    fn data_before_keyword_is_an_error() {
        let e = lex("\n1, 2\n*KEYWORD\n", "f").unwrap_err();
        assert_eq!(e.line, Some(2));
    }
}
