//! The LS-DYNA keyword deck reader: lexing, field decoding, and building a `Model`; and the
//! writer that turns a `Model` back into a deck.
//!
//! Reading is done in three passes: [`lex`] splits the text into keyword blocks (`include`
//! puts the blocks of included files in place of their `*INCLUDE`s), `cards`
//! decodes each supported keyword's cards into a raw deck (deck ids, with their lines), and
//! `build` resolves every reference into the dense indices of a
//! [`Model`]. Card layouts are those of the LS-DYNA Keyword
//! User's Manual; the supported subset is listed in `shared/spec/interface.md`.

mod build;
mod cards;
mod error;
mod expr;
pub mod fields;
mod include;
pub mod lex;
mod params;
mod raw;
mod transform;
pub(crate) mod write;

use std::path::Path;

use cleave_core::model::Model;

pub use error::DeckError;
pub use write::write_deck;

/// A deck that was read and validated.
#[derive(Clone, Debug)]
pub struct Deck {
    pub model: Model,
    /// Things read but not used (ignored options, unsupported output requests), one per line.
    pub warnings: Vec<String>,
    /// Every keyword read (as written, upper case), with how many times, in order of first
    /// appearance; the files read (the deck and what it includes).
    pub keywords: Vec<(String, usize)>,
    pub files: Vec<String>,
}

/// Reads and validates the deck at `path`. Bytes that are not UTF-8 are replaced (they then
/// fail as "not a number" where they matter); errors name the file as given.
pub fn read_deck(path: &Path) -> Result<Deck, DeckError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| DeckError::deck(&file, format!("cannot read the deck: {e}")))?;
    let text = String::from_utf8_lossy(&bytes);
    parse_deck(&text, &file)
}

/// Parses and validates a deck given as text; `file` names it in messages, and the files it
/// includes (`*INCLUDE`) are looked for beside it.
pub fn parse_deck(text: &str, file: &str) -> Result<Deck, DeckError> {
    if text.trim().is_empty() {
        return Err(DeckError::deck(file, "the deck is empty"));
    }
    let sources = include::collect(text, file)?;
    let blocks = include::blocks(&sources)?;
    if blocks.is_empty() {
        return Err(DeckError::deck(file, "the deck has no keywords"));
    }
    let mut keywords: Vec<(String, usize)> = Vec::new();
    for b in &blocks {
        match keywords.iter_mut().find(|(k, _)| *k == b.keyword) {
            Some((_, n)) => *n += 1,
            None => keywords.push((b.keyword.clone(), 1)),
        }
    }
    let mut files: Vec<String> = Vec::new();
    for b in &blocks {
        if !files.iter().any(|f| **f == *b.file) {
            files.push(b.file.to_string());
        }
    }
    let mut raw = transform::read(&blocks)?;
    let mut warnings = std::mem::take(&mut raw.warnings);
    let (model, more) = build::build(raw, file)?;
    warnings.extend(more);
    Ok(Deck {
        model,
        warnings,
        keywords,
        files,
    })
}
