//! The deck reader's one error type: a message that says where (file, line, keyword, field)
//! and what is wrong.

use std::fmt;

/// An error in a keyword deck. `Display` gives one line such as
/// `deck.k:42: *NODE: field X: 'abc' is not a number`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeckError {
    /// The deck's file name as given to the reader.
    pub file: String,
    /// 1-based line number, when the error belongs to one line.
    pub line: Option<usize>,
    /// The keyword (as written, upper case, with its `*`) of the card at fault.
    pub keyword: Option<String>,
    /// The field name as in the LS-DYNA manual (e.g. `SECID`), when one field is at fault.
    pub field: Option<String>,
    /// What is wrong (names the entity id where one applies).
    pub message: String,
}

impl DeckError {
    /// An error about the deck as a whole.
    pub fn deck(file: &str, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            line: None,
            keyword: None,
            field: None,
            message: message.into(),
        }
    }

    /// An error at a line, optionally inside a keyword's data.
    pub fn at(file: &str, line: usize, keyword: Option<&str>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            line: Some(line),
            keyword: keyword.map(str::to_string),
            field: None,
            message: message.into(),
        }
    }

    /// The same error, naming the field at fault.
    pub fn with_field(mut self, field: &str) -> Self {
        self.field = Some(field.to_string());
        self
    }
}

impl fmt::Display for DeckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if let Some(kw) = &self.keyword {
            write!(f, "{kw}: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "field {field}: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for DeckError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_line_keyword_field() {
        let e = DeckError::at("deck.k", 42, Some("*NODE"), "'abc' is not a number").with_field("X");
        assert_eq!(
            e.to_string(),
            "deck.k:42: *NODE: field X: 'abc' is not a number"
        );
        assert_eq!(
            DeckError::deck("a.k", "empty deck").to_string(),
            "a.k: empty deck"
        );
    }
}
