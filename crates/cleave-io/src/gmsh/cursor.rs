//! A cursor over the bytes of an MSH file: the ASCII lines and tokens every file has (section
//! markers, `$MeshFormat`'s header, `$PhysicalNames`, MSH 2.2's counts), and the data values,
//! read as ASCII tokens or as binary numbers as the file's `$MeshFormat` says.
//!
//! Binary values (Gmsh reference manual, "MSH file format"): `int` is 4 bytes, `double` 8, and
//! MSH 4.1's `size_t` is `data-size` bytes (4 or 8); all in the byte order of the machine that
//! wrote the file, which the integer 1 written after the header tells (read byte-swapped, it
//! is 16777216: the file is big-endian and every value is read so).
//!
//! Errors are placed by line (1-based) in an ASCII file and by byte offset (0-based) in a
//! binary one; nothing here panics on any input.

use super::error::{At, MshError};

/// Where a value is read: the file's bytes and its encoding.
pub struct Cursor<'a> {
    file: &'a str,
    bytes: &'a [u8],
    pos: usize,
    /// The data is binary (MSH file-type 1).
    binary: bool,
    /// The file is big-endian (values are read little-endian otherwise).
    swap: bool,
    /// Bytes of a `size_t` (MSH 4.1 binary: data-size).
    size_t: usize,
    /// Where the ASCII record (one line: a node, an element) being read starts, if one is.
    record: Option<usize>,
}

type R<T> = Result<T, MshError>;

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | b'\x0c' | b'\x0b')
}

impl<'a> Cursor<'a> {
    pub fn new(file: &'a str, bytes: &'a [u8]) -> Self {
        Self {
            file,
            bytes,
            pos: 0,
            binary: false,
            swap: false,
            size_t: 8,
            record: None,
        }
    }

    pub fn file(&self) -> &'a str {
        self.file
    }

    /// From here on data values are binary, `size_t` being `size_t` bytes.
    pub fn set_binary(&mut self, size_t: usize) {
        self.binary = true;
        self.size_t = size_t;
    }

    pub fn is_binary(&self) -> bool {
        self.binary
    }

    /// Where the next value starts (in an ASCII file, past the white space before it).
    pub fn mark(&mut self) -> usize {
        if !self.binary {
            self.skip_space();
        }
        self.pos
    }

    /// The place of byte `pos`: its line in an ASCII file, the offset in a binary one.
    pub fn place(&self, pos: usize) -> At {
        if self.binary {
            At::Byte(pos)
        } else {
            let end = pos.min(self.bytes.len());
            At::Line(self.bytes[..end].iter().filter(|&&b| b == b'\n').count() + 1)
        }
    }

    /// An error at byte `pos`.
    pub fn err_at(&self, pos: usize, message: impl Into<String>) -> MshError {
        MshError {
            file: self.file.to_string(),
            at: Some(self.place(pos)),
            message: message.into(),
        }
    }

    fn eof(&self, what: &str) -> MshError {
        self.err_at(
            self.bytes.len(),
            format!("the file ends while reading {what} (is it truncated?)"),
        )
    }

    fn skip_space(&mut self) {
        while self.pos < self.bytes.len() && is_space(self.bytes[self.pos]) {
            self.pos += 1;
        }
    }

    /// True when only white space is left.
    pub fn at_end(&mut self) -> bool {
        self.skip_space();
        self.pos >= self.bytes.len()
    }

    /// The next non-blank line, trimmed, and where it starts; the cursor moves past its
    /// newline (where a binary section's data starts).
    pub fn line(&mut self, what: &str) -> R<(usize, &'a str)> {
        self.skip_space();
        let start = self.pos;
        if start >= self.bytes.len() {
            return Err(self.eof(what));
        }
        let end = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.bytes.len(), |k| start + k);
        self.pos = (end + 1).min(self.bytes.len());
        std::str::from_utf8(&self.bytes[start..end])
            .map(|s| (start, s.trim()))
            .map_err(|_| {
                self.err_at(
                    start,
                    format!("expected {what}, found bytes that are not text"),
                )
            })
    }

    /// The next ASCII token (a run of non-blank bytes) and where it starts. Inside a record,
    /// the end of its line is an error: values are missing there.
    pub fn token(&mut self, what: &str) -> R<(usize, &'a str)> {
        if let Some(start) = self.record {
            while self.pos < self.bytes.len() && is_space(self.bytes[self.pos]) {
                if self.bytes[self.pos] == b'\n' {
                    return Err(self.err_at(
                        start,
                        format!("the line ends where {what} should be: values are missing"),
                    ));
                }
                self.pos += 1;
            }
        }
        self.skip_space();
        let start = self.pos;
        while self.pos < self.bytes.len() && !is_space(self.bytes[self.pos]) {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.eof(what));
        }
        std::str::from_utf8(&self.bytes[start..self.pos])
            .map(|s| (start, s))
            .map_err(|_| {
                self.err_at(
                    start,
                    format!("expected {what}, found bytes that are not text"),
                )
            })
    }

    /// Moves past the end of the current line (after an ASCII count that binary data follows).
    pub fn rest_of_line(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos] != b'\n' {
            self.pos += 1;
        }
        self.pos = (self.pos + 1).min(self.bytes.len());
    }

    /// In an ASCII file, checks that the values read since `start` were one line, the whole
    /// line: a record (a node, an element) with values missing or extra is an error at its
    /// line, not a confusing one further on. Binary files have no lines: nothing to check.
    pub fn record_end(&mut self, start: usize, what: &str) -> R<()> {
        if self.binary {
            return Ok(());
        }
        self.record = None;
        let end = self.pos.min(self.bytes.len());
        let from = start.min(end);
        if self.bytes[from..end].contains(&b'\n') {
            return Err(self.err_at(
                start,
                format!("{what} has fewer values on its line than its type needs"),
            ));
        }
        while self.pos < self.bytes.len() && matches!(self.bytes[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
        if self.pos < self.bytes.len() && self.bytes[self.pos] != b'\n' {
            return Err(self.err_at(
                start,
                format!("{what} has more values on its line than its type needs"),
            ));
        }
        Ok(())
    }

    /// Starts a record that must be one line of an ASCII file (see [`Self::record_end`]);
    /// returns where it starts.
    pub fn begin_record(&mut self) -> usize {
        let at = self.mark();
        if !self.binary {
            self.record = Some(at);
        }
        at
    }

    /// An ASCII integer token.
    pub fn ascii_int(&mut self, what: &str) -> R<i64> {
        let (at, t) = self.token(what)?;
        t.parse::<i64>().map_err(|_| {
            self.err_at(
                at,
                format!("expected {what} (an integer), found '{}'", shorten(t)),
            )
        })
    }

    /// An ASCII count: a non-negative integer token.
    pub fn ascii_count(&mut self, what: &str) -> R<u64> {
        let (at, t) = self.token(what)?;
        t.parse::<u64>().map_err(|_| {
            self.err_at(
                at,
                format!(
                    "expected {what} (a count, 0 or more), found '{}'",
                    shorten(t)
                ),
            )
        })
    }

    fn take(&mut self, n: usize, what: &str) -> R<&'a [u8]> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| self.eof(what))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn bin_u64(&mut self, n: usize, what: &str) -> R<u64> {
        let s = self.take(n, what)?;
        let mut v: u64 = 0;
        let mut push = |b: &u8| v = (v << 8) | u64::from(*b);
        // little-endian unless swapped: the last byte is the most significant
        if self.swap {
            s.iter().for_each(&mut push);
        } else {
            s.iter().rev().for_each(&mut push);
        }
        Ok(v)
    }

    /// An `int`: an ASCII token, or 4 binary bytes.
    pub fn int(&mut self, what: &str) -> R<i64> {
        if self.binary {
            Ok(i64::from(self.bin_u64(4, what)? as u32 as i32))
        } else {
            self.ascii_int(what)
        }
    }

    /// A `size_t` (a count or a tag, MSH 4.1): an ASCII token, or data-size binary bytes.
    pub fn size(&mut self, what: &str) -> R<u64> {
        if self.binary {
            self.bin_u64(self.size_t, what)
        } else {
            self.ascii_count(what)
        }
    }

    /// A `double`: an ASCII token, or 8 binary bytes.
    pub fn float(&mut self, what: &str) -> R<f64> {
        if self.binary {
            Ok(f64::from_bits(self.bin_u64(8, what)?))
        } else {
            let (at, t) = self.token(what)?;
            t.parse::<f64>().map_err(|_| {
                self.err_at(
                    at,
                    format!("expected {what} (a number), found '{}'", shorten(t)),
                )
            })
        }
    }

    /// Reads the binary integer 1 after a binary file's header and sets the byte order by it.
    pub fn endianness(&mut self) -> R<()> {
        let at = self.pos;
        let s = self.take(4, "the binary check integer 1")?;
        // values are assembled byte by byte, so the host's own byte order does not matter
        match s {
            [1, 0, 0, 0] => self.swap = false,
            [0, 0, 0, 1] => self.swap = true,
            _ => {
                return Err(self.err_at(
                    at,
                    format!(
                        "the binary check integer is not 1 (bytes {s:02x?}): not a binary MSH file, or a damaged one"
                    ),
                ))
            }
        }
        Ok(())
    }

    /// The `$End...` line closing `section` (e.g. `$Nodes`); anything else there means the
    /// counts did not match the data.
    pub fn expect_end(&mut self, section: &str) -> R<()> {
        let want = format!("$End{}", &section[1..]);
        let (at, line) = self.line(&want)?;
        if line == want {
            Ok(())
        } else {
            Err(self.err_at(
                at,
                format!(
                    "expected {want}, found '{}' (do the counts of {section} match its data?)",
                    shorten(line)
                ),
            ))
        }
    }

    /// Skips an unknown section, whose name line starts at `at`, up to its `$End...` line.
    pub fn skip_section(&mut self, section: &str, at: usize) -> R<()> {
        let want = format!("\n$End{}", &section[1..]);
        let from = at.min(self.bytes.len());
        let hay = &self.bytes[from..];
        match hay.windows(want.len()).position(|w| w == want.as_bytes()) {
            Some(k) => {
                self.pos = from + k + want.len();
                Ok(())
            }
            None => Err(self.err_at(
                at,
                format!("section {section} has no $End{} line", &section[1..]),
            )),
        }
    }
}

/// At most 40 characters of `s`, control characters escaped, for messages (the deck
/// reader's rule).
pub fn shorten(s: &str) -> String {
    crate::deck::fields::show(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_lines_and_places() {
        let text = b"$Nodes\n1 2\n  x\n";
        let mut c = Cursor::new("f.msh", text);
        assert_eq!(c.line("a section").unwrap(), (0, "$Nodes"));
        assert_eq!(c.ascii_int("n").unwrap(), 1);
        assert_eq!(c.size("n").unwrap(), 2);
        let e = c.float("x").unwrap_err();
        assert_eq!(e.at, Some(At::Line(3)));
        assert!(e.message.contains("'x'"), "{e}");
        let e = c.int("more").unwrap_err();
        assert_eq!(e.at, Some(At::Line(4)));
        assert!(e.message.contains("truncated"), "{e}");
    }

    #[test]
    fn binary_values_both_byte_orders() {
        let mut le = Vec::new();
        le.extend(1i32.to_le_bytes());
        le.extend((-5i32).to_le_bytes());
        le.extend(7u64.to_le_bytes());
        le.extend(0.1f64.to_le_bytes());
        let mut be = Vec::new();
        be.extend(1i32.to_be_bytes());
        be.extend((-5i32).to_be_bytes());
        be.extend(7u64.to_be_bytes());
        be.extend(0.1f64.to_be_bytes());
        for bytes in [le, be] {
            let mut c = Cursor::new("b.msh", &bytes);
            c.set_binary(8);
            c.endianness().unwrap();
            assert_eq!(c.int("i").unwrap(), -5);
            assert_eq!(c.size("s").unwrap(), 7);
            assert_eq!(c.float("d").unwrap().to_bits(), 0.1f64.to_bits());
            let e = c.int("past the end").unwrap_err();
            assert_eq!(e.at, Some(At::Byte(bytes.len())));
        }
    }

    #[test]
    fn bad_check_integer_is_an_error() {
        let mut c = Cursor::new("b.msh", b"\x02\x00\x00\x00");
        c.set_binary(8);
        let e = c.endianness().unwrap_err();
        assert_eq!(e.at, Some(At::Byte(0)));
    }

    #[test]
    fn unknown_sections_are_skipped_by_name() {
        for text in [
            &b"$NodeData\n1\n2\n$EndNodeData\n$Nodes\n"[..],
            b"$X\n$EndX\n$Nodes",
        ] {
            let mut c = Cursor::new("f.msh", text);
            let (at, name) = c.line("a section").unwrap();
            c.skip_section(name, at).unwrap();
            assert_eq!(c.line("a section").unwrap().1, "$Nodes");
        }
        let mut c = Cursor::new("f.msh", b"$Junk\n1\n");
        let (at, name) = c.line("a section").unwrap();
        assert!(c.skip_section(name, at).is_err());
    }
}
