//! `*INCLUDE`: a deck split over several files is read as one, each block keeping the file it
//! came from, so every message names the file and line where the card is.
//!
//! - `*INCLUDE`: each data line names a file (a name longer than a line continues on the next
//!   when the line ends with ` +`, as LS-DYNA's 80-column cards do). Its keywords take the
//!   place of the `*INCLUDE` in the deck; `*END` ends only the included file.
//! - Where a name is looked for: as given when absolute; otherwise first beside the file that
//!   includes it, then in the `*INCLUDE_PATH` / `*INCLUDE_PATH_RELATIVE` directories read so
//!   far (each line one directory, relative ones taken from the main deck's directory). LS-DYNA
//!   looks in the directory it runs in first; cleave runs from anywhere, so the including
//!   file's directory stands in for it.
//! - A file whose name ends in `.msh` is a Gmsh mesh: it is read by [`crate::gmsh`] and stands
//!   in the deck as its keyword text (`*NODE`, `*ELEMENT_SOLID`, `*SET_NODE_LIST`,
//!   `*SET_SEGMENT`), the deck's own `*PART` cards giving the physical volumes' part ids their
//!   section and material.
//! - `*INCLUDE_TRANSFORM`: the file named on its first card is read as a group of its own
//!   (its blocks carry the group's number, [`Block::group`]), whose ids are offset and whose
//!   nodes are moved as the keyword's further cards say (`super::transform`). A transformed
//!   include inside another one is an error.
//! - A file that includes itself, directly or through others, is an error naming the chain;
//!   so are a missing file (naming the places searched) and the `*INCLUDE_...` variants that
//!   offset or convert what they read in other ways (`_AUTO_OFFSET`, `_NASTRAN`,
//!   `_STAMPED_PART`, ...), which cleave does not apply.

use std::path::{Path, PathBuf};

use super::error::DeckError;
use super::fields::Format;
use super::lex::{lex, Block};

/// How deep includes may nest (a guard against runaway recursion; real decks use 2 or 3).
pub const MAX_DEPTH: usize = 32;

/// One file of the deck, with the files its `*INCLUDE`s read, by the line of the `*INCLUDE`.
#[derive(Debug)]
pub struct Source {
    file: String,
    text: String,
    includes: Vec<(usize, Vec<usize>)>,
}

/// Reads the deck `text` (the file `file`) and every file it includes, recursively.
pub fn collect(text: &str, file: &str) -> Result<Vec<Source>, DeckError> {
    let mut sources = vec![Source {
        file: file.to_string(),
        text: text.to_string(),
        includes: Vec::new(),
    }];
    let main_dir = dir_of(file);
    let mut search = Vec::new();
    visit(
        0,
        false,
        &mut vec![file.to_string()],
        &main_dir,
        &mut search,
        &mut sources,
    )?;
    Ok(sources)
}

/// The blocks of the whole deck in reading order, the included files' in place of their
/// `*INCLUDE`s.
pub fn blocks(sources: &[Source]) -> Result<Vec<Block<'_>>, DeckError> {
    let mut lexed: Vec<Option<Vec<Block<'_>>>> = Vec::with_capacity(sources.len());
    for s in sources {
        lexed.push(Some(lex(&s.text, &s.file)?));
    }
    let mut out = Vec::new();
    let mut groups = 0;
    flatten(
        (0, 0, Format::Standard),
        sources,
        &mut lexed,
        &mut groups,
        &mut out,
    );
    Ok(out)
}

/// Appends the blocks of source `i` to `out`, in group `group`; an `*INCLUDE_TRANSFORM` opens
/// the next group (`groups` counts them) and is kept, marked with that group, for its cards to
/// be read. A block whose layout neither its keyword nor its file's `*KEYWORD` line sets gets
/// `inherited`, that of the `*INCLUDE` that brought its file in.
fn flatten<'a>(
    (i, group, inherited): (usize, usize, Format),
    sources: &[Source],
    lexed: &mut [Option<Vec<Block<'a>>>],
    groups: &mut usize,
    out: &mut Vec<Block<'a>>,
) {
    let Some(blocks) = lexed[i].take() else {
        return;
    };
    for mut b in blocks {
        let format = b.format.unwrap_or(inherited);
        b.format = Some(format);
        let children = || {
            sources[i]
                .includes
                .iter()
                .find(|(line, _)| *line == b.line)
                .map(|(_, c)| c.clone())
                .unwrap_or_default()
        };
        if b.keyword == "*INCLUDE" {
            for c in children() {
                flatten((c, group, format), sources, lexed, groups, out);
            }
        } else if b.keyword == "*INCLUDE_TRANSFORM" {
            *groups += 1;
            let g = *groups;
            let cs = children();
            b.group = g;
            out.push(b);
            for c in cs {
                flatten((c, g, format), sources, lexed, groups, out);
            }
        } else if !b.keyword.starts_with("*INCLUDE_PATH") {
            b.group = group;
            out.push(b);
        }
    }
}

/// How many of a block's lines its file name takes: the first line, and the lines after it
/// while each ends with ` +` (the continuation of a long name).
pub fn name_lines(lines: &[super::lex::Line<'_>]) -> usize {
    lines
        .iter()
        .position(|l| !l.text.trim().ends_with(" +"))
        .map_or(lines.len(), |k| k + 1)
}

/// The directory of `file` (the current directory for a bare name).
fn dir_of(file: &str) -> PathBuf {
    Path::new(file)
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// The names on an `*INCLUDE` block's lines, joining the lines that end with ` +`.
fn names(block: &Block<'_>) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut pending: Option<(usize, String)> = None;
    for l in &block.lines {
        let t = l.text.trim();
        if t.is_empty() && pending.is_none() {
            continue;
        }
        let (line, mut name) = pending.take().unwrap_or((l.no, String::new()));
        match t.strip_suffix(" +") {
            Some(head) => {
                name.push_str(head.trim_end());
                pending = Some((line, name));
            }
            None => {
                name.push_str(t);
                out.push((line, name));
            }
        }
    }
    out.extend(pending);
    out
}

/// Reads source `i`'s includes, recursively; `in_xform` when it is read through an
/// `*INCLUDE_TRANSFORM` (directly or through plain includes).
fn visit(
    i: usize,
    in_xform: bool,
    chain: &mut Vec<String>,
    main_dir: &Path,
    search: &mut Vec<PathBuf>,
    sources: &mut Vec<Source>,
) -> Result<(), DeckError> {
    let file = sources[i].file.clone();
    let here = dir_of(&file);
    // the blocks are lexed again, borrowing the text, when the deck is read (`blocks`); the
    // text is taken out while `sources` grows (on an error the sources are dropped anyway)
    let text = std::mem::take(&mut sources[i].text);
    {
        let found = lex(&text, &file)?;
        let mut includes = Vec::new();
        for b in &found {
            let kw = b.keyword.as_str();
            match kw {
                "*INCLUDE" => {
                    let mut children = Vec::new();
                    for (line, name) in names(b) {
                        let at = |m: String| DeckError::at(&file, line, Some(kw), m);
                        let walk = Walk {
                            here: &here,
                            in_xform,
                            main_dir,
                        };
                        children.push(walk.include(&name, at, chain, search, sources)?);
                    }
                    includes.push((b.line, children));
                }
                "*INCLUDE_TRANSFORM" => {
                    let at = |line: usize, m: String| DeckError::at(&file, line, Some(kw), m);
                    if in_xform {
                        return Err(at(
                            b.line,
                            "an *INCLUDE_TRANSFORM inside a file read through another one is not supported (cleave does not compose the two transformations)".into(),
                        ));
                    }
                    let k = name_lines(&b.lines);
                    let Some((line, name)) = names(&Block {
                        lines: b.lines[..k].to_vec(),
                        ..b.clone()
                    })
                    .into_iter()
                    .next() else {
                        return Err(at(b.line, "missing card (the file name)".into()));
                    };
                    let walk = Walk {
                        here: &here,
                        in_xform: true,
                        main_dir,
                    };
                    let child = walk.include(&name, |m| at(line, m), chain, search, sources)?;
                    includes.push((b.line, vec![child]));
                }
                "*INCLUDE_PATH" | "*INCLUDE_PATH_RELATIVE" => {
                    for (_, dir) in names(b) {
                        let d = Path::new(&dir);
                        search.push(if d.is_absolute() {
                            d.to_path_buf()
                        } else {
                            main_dir.join(d)
                        });
                    }
                }
                k if k.starts_with("*INCLUDE") => {
                    return Err(DeckError::at(
                        &file,
                        b.line,
                        Some(k),
                        "not supported (cleave reads *INCLUDE, *INCLUDE_PATH, *INCLUDE_PATH_RELATIVE and *INCLUDE_TRANSFORM)",
                    ))
                }
                _ => {}
            }
        }
        sources[i].includes = includes;
    }
    sources[i].text = text;
    Ok(())
}

/// Where an include is read from: the including file's directory, whether it is read
/// through an `*INCLUDE_TRANSFORM`, the main deck's directory.
struct Walk<'a> {
    here: &'a Path,
    in_xform: bool,
    main_dir: &'a Path,
}

impl Walk<'_> {
    /// Reads the file `name` (and what it includes) into `sources`; returns its index. `at`
    /// makes an error at the name's line. Errors: nesting too deep, a file not found, one that
    /// includes itself, one that cannot be read.
    fn include(
        &self,
        name: &str,
        at: impl Fn(String) -> DeckError,
        chain: &mut Vec<String>,
        search: &mut Vec<PathBuf>,
        sources: &mut Vec<Source>,
    ) -> Result<usize, DeckError> {
        if chain.len() > MAX_DEPTH {
            return Err(at(format!("includes nest deeper than {MAX_DEPTH} files")));
        }
        let path = resolve(name, self.here, search).map_err(&at)?;
        let shown = path.display().to_string();
        let key = canonical(&path);
        if let Some(k) = chain.iter().position(|f| canonical(Path::new(f)) == key) {
            return Err(at(format!(
                "'{name}' includes itself: {} -> {shown}",
                chain[k..].join(" -> ")
            )));
        }
        let bytes = std::fs::read(&path).map_err(|e| at(format!("cannot read '{shown}': {e}")))?;
        if is_msh(&path) {
            sources.push(msh_source(&bytes, &shown)?);
            return Ok(sources.len() - 1);
        }
        sources.push(Source {
            file: shown.clone(),
            text: String::from_utf8_lossy(&bytes).into_owned(),
            includes: Vec::new(),
        });
        let child = sources.len() - 1;
        chain.push(shown);
        visit(child, self.in_xform, chain, self.main_dir, search, sources)?;
        chain.pop();
        Ok(child)
    }
}

/// True for a Gmsh mesh: a name ending in `.msh` (any case).
fn is_msh(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("msh"))
}

/// A Gmsh mesh (the file `shown`) as the keyword text `cleave import` writes for it: nodes,
/// solids, node and segment sets ([`crate::gmsh`]). An error in the mesh names the .msh and
/// its line (or byte, in a binary file); the text is named `NAME.msh (converted)`, so that an
/// error the deck finds in it (a part the deck does not define) names the mesh and the line of
/// the text `cleave import NAME.msh` writes.
fn msh_source(bytes: &[u8], shown: &str) -> Result<Source, DeckError> {
    let mesh = crate::gmsh::parse_msh(bytes, shown)?;
    Ok(Source {
        file: format!("{shown} (converted)"),
        text: crate::gmsh::keyword_text(&mesh, shown),
        includes: Vec::new(),
    })
}

/// Where `name` is: absolute as given, else beside the including file (`here`), else in the
/// search directories; the error lists the places tried.
fn resolve(name: &str, here: &Path, search: &[PathBuf]) -> Result<PathBuf, String> {
    if name.is_empty() {
        return Err("an empty file name".into());
    }
    let p = Path::new(name);
    if p.is_absolute() {
        return Ok(p.to_path_buf());
    }
    let tried: Vec<PathBuf> = std::iter::once(here.join(p))
        .chain(search.iter().map(|d| d.join(p)))
        .collect();
    if let Some(found) = tried.iter().find(|t| t.is_file()) {
        return Ok(found.clone());
    }
    Err(format!(
        "cannot find '{name}' (looked in: {})",
        tried
            .iter()
            .map(|t| t.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    ))
}

/// A path's canonical form when it exists (to see a file included twice under two names).
fn canonical(p: &Path) -> PathBuf {
    p.canonicalize().unwrap_or_else(|_| p.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_join_continued_lines() {
        let text = "*INCLUDE\nparts/a.k\nvery/long/dir +\n/b.k\n\nc.k\n";
        let b = lex(text, "m.k").unwrap();
        let n = names(&b[0]);
        assert_eq!(
            n,
            vec![
                (2, "parts/a.k".to_string()),
                (3, "very/long/dir/b.k".to_string()),
                (6, "c.k".to_string())
            ]
        );
    }

    #[test]
    fn dir_of_a_bare_name_is_here() {
        assert_eq!(dir_of("deck.k"), PathBuf::from("."));
        assert_eq!(dir_of("a/b/deck.k"), PathBuf::from("a/b"));
    }
}
