//! The Gmsh reader's error: the file, where in it (a line of an ASCII file, a byte offset of a
//! binary one) and what is wrong.

use std::fmt;

/// Where in the file an error is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum At {
    /// 1-based line of an ASCII file.
    Line(usize),
    /// 0-based byte offset in a binary file (its ASCII parts included, so that one rule holds
    /// for the whole file).
    Byte(usize),
}

/// An error in a Gmsh MSH file. `Display` gives one line such as
/// `box.msh:42: element 17 refers to node 99, which $Nodes does not define`, or
/// `box.msh: byte 1234: ...` for a binary file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MshError {
    /// The file name as given to the reader.
    pub file: String,
    /// Where, when the error belongs to one place of the file.
    pub at: Option<At>,
    /// What is wrong.
    pub message: String,
}

impl MshError {
    /// An error about the file as a whole.
    pub fn file(file: &str, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            at: None,
            message: message.into(),
        }
    }

    /// The line (1-based), when the error has one (ASCII files).
    pub fn line(&self) -> Option<usize> {
        match self.at {
            Some(At::Line(l)) => Some(l),
            _ => None,
        }
    }
}

impl fmt::Display for MshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            Some(At::Line(l)) => write!(f, "{}:{l}: {}", self.file, self.message),
            Some(At::Byte(b)) => write!(f, "{}: byte {b}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for MshError {}

/// A mesh error as a deck error (a mesh `*INCLUDE`d in a deck): the same file and line; a
/// byte offset goes into the message, as `Display` writes it.
impl From<MshError> for crate::deck::DeckError {
    fn from(e: MshError) -> Self {
        let (line, message) = match e.at {
            Some(At::Line(l)) => (Some(l), e.message),
            Some(At::Byte(b)) => (None, format!("byte {b}: {}", e.message)),
            None => (None, e.message),
        };
        Self {
            file: e.file,
            line,
            keyword: None,
            field: None,
            message,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_and_place() {
        let mut e = MshError::file("a.msh", "bad");
        assert_eq!(e.to_string(), "a.msh: bad");
        e.at = Some(At::Line(3));
        assert_eq!(e.to_string(), "a.msh:3: bad");
        let d: crate::deck::DeckError = e.clone().into();
        assert_eq!(d.to_string(), e.to_string());
        e.at = Some(At::Byte(40));
        assert_eq!(e.to_string(), "a.msh: byte 40: bad");
        let d: crate::deck::DeckError = e.clone().into();
        assert_eq!(d.to_string(), e.to_string());
    }
}
