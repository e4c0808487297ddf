//! Arrays larger than the device binds: one buffer, bound as several ranges.
//!
//! A storage binding holds at most `max_storage_buffer_binding_size` bytes (128 MiB on
//! lavapipe, 2 GiB on an H100 through Vulkan), while a buffer may be larger
//! (`max_buffer_size`: 2 GiB on Mesa, the memory on NVIDIA). An array whose buffer exceeds the
//! binding limit is bound as consecutive *chunks* of `len` values each (the last shorter):
//! chunk 0 at the array's own binding under its own name, chunk c at a fresh binding as
//! `NAME_c`, each starting at a multiple of `min_storage_buffer_offset_alignment`. The shader
//! text is rewritten so that every access `NAME[i]` of a split array goes through
//! `NAME_get(i)` (value i lives in chunk `i / len` at `i % len`) and every store
//! `NAME[i] = v` through `NAME_put(i, v)`. Arrays that fit are left as they are, so a model
//! that needs no splitting runs the shader text unchanged. The host keeps one buffer per
//! array either way, so uploads, read-backs and restart files do not change, and neither do
//! the results (the same operations in the same order: a split run gives the same bits,
//! `tests/split_arrays.rs`).

/// A storage array of the shader that can be split: its binding, name and value size.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Decl {
    pub binding: u32,
    pub name: String,
    /// "f64" or "u32".
    pub ty: String,
    pub read_only: bool,
}

/// A chunk of an array: its binding, byte offset and byte size.
pub(crate) type Chunk = (u32, u64, u64);

/// How one array is bound.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Split {
    pub decl: Decl,
    /// Values per chunk.
    pub len: u64,
    /// (binding, byte offset, byte size) of each chunk; the first is the array's own binding.
    pub chunks: Vec<Chunk>,
}

/// The splittable storage arrays declared in `src` ([`declared`]).
pub(crate) fn declarations(src: &str) -> Vec<Decl> {
    src.lines().filter_map(declared).collect()
}

/// The array a line declares, when it is
/// `@group(0) @binding(B) var<storage, read|read_write> NAME: array<f64|u32>;` (arrays of
/// atomics, the uniform and workgroup arrays cannot be split).
fn declared(line: &str) -> Option<Decl> {
    let rest = line.trim().strip_prefix("@group(0) @binding(")?;
    let (b, rest) = rest.split_once(')')?;
    let binding = b.parse().ok()?;
    let rest = rest.trim();
    let (read_only, rest) = if let Some(r) = rest.strip_prefix("var<storage, read>") {
        (true, r)
    } else {
        (false, rest.strip_prefix("var<storage, read_write>")?)
    };
    let (name, ty) = rest.split_once(':')?;
    let ty = match ty.trim().trim_end_matches(';').trim() {
        "array<f64>" => "f64",
        "array<u32>" => "u32",
        _ => return None,
    };
    Some(Decl {
        binding,
        name: name.trim().to_string(),
        ty: ty.to_string(),
        read_only,
    })
}

impl Decl {
    /// Bytes of one value.
    fn value_bytes(&self) -> u64 {
        if self.ty == "f64" {
            8
        } else {
            4
        }
    }
}

/// The chunks of array `decl` of `bytes` bytes under a binding limit `limit` and an offset
/// alignment `align`: None when it fits one binding. Chunks after the first take bindings
/// from `*next`.
pub(crate) fn plan(
    decl: &Decl,
    bytes: u64,
    limit: u64,
    align: u64,
    next: &mut u32,
) -> Option<Split> {
    if bytes <= limit {
        return None;
    }
    let value = decl.value_bytes();
    // the largest chunk that binds and keeps the next chunk's offset aligned
    let step = align.max(value) / value * value;
    let chunk = (limit / step * step).max(step);
    let len = chunk / value;
    let mut chunks = vec![];
    let mut offset = 0;
    while offset < bytes {
        let size = chunk.min(bytes - offset);
        let binding = if offset == 0 {
            decl.binding
        } else {
            *next += 1;
            *next - 1
        };
        chunks.push((binding, offset, size));
        offset += size;
    }
    Some(Split {
        decl: decl.clone(),
        len,
        chunks,
    })
}

/// `src` with every access to the arrays of `splits` through their accessors, the chunks'
/// declarations after each array's own, and the accessors appended.
pub(crate) fn rewrite(src: &str, splits: &[Split]) -> String {
    if splits.is_empty() {
        return src.to_string();
    }
    let names: Vec<&str> = splits.iter().map(|s| s.decl.name.as_str()).collect();
    let mut out = String::with_capacity(src.len() + 4096);
    for line in src.lines() {
        out.push_str(line);
        out.push('\n');
        // the chunks' declarations beside the array's
        let Some(d) = declared(line) else { continue };
        let Some(s) = splits.iter().find(|s| s.decl.binding == d.binding) else {
            continue;
        };
        let access = if d.read_only { "read" } else { "read_write" };
        for (c, &(binding, _, _)) in s.chunks.iter().enumerate().skip(1) {
            out.push_str(&format!(
                "@group(0) @binding({binding}) var<storage, {access}> {}_{c}: array<{}>;\n",
                d.name, d.ty
            ));
        }
    }
    let mut text = accesses(&out, &names);
    for s in splits {
        text.push_str(&accessors(s));
    }
    text
}

/// The accessor functions of one split array.
fn accessors(s: &Split) -> String {
    let (name, ty, len) = (&s.decl.name, &s.decl.ty, s.len);
    let chunk = |c: usize| {
        if c == 0 {
            name.clone()
        } else {
            format!("{name}_{c}")
        }
    };
    let cases = |body: &dyn Fn(&str) -> String| {
        let mut t = String::new();
        let last = s.chunks.len() - 1;
        for c in 0..=last {
            let label = if c == last {
                "default".to_string()
            } else {
                format!("case {c}u")
            };
            t.push_str(&format!("        {label}: {{ {} }}\n", body(&chunk(c))));
        }
        t
    };
    let mut f = format!(
        "\n// {name}: {} chunks of {len} values (split.rs)\nfn {name}_get(i: u32) -> {ty} {{\n    let c = i / {len}u;\n    let j = i - c * {len}u;\n    switch c {{\n{}    }}\n}}\n",
        s.chunks.len(),
        cases(&|a| format!("return {a}[j];"))
    );
    if !s.decl.read_only {
        f.push_str(&format!(
            "fn {name}_put(i: u32, val: {ty}) {{\n    let c = i / {len}u;\n    let j = i - c * {len}u;\n    switch c {{\n{}    }}\n}}\n",
            cases(&|a| format!("{a}[j] = val;"))
        ));
    }
    f
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The end (index after) of the bracketed text that opens at `open` (`src[open]` is `[`).
fn close(src: &[u8], open: usize) -> usize {
    let mut depth = 0i32;
    let mut i = open;
    while i < src.len() {
        match src[i] {
            b'[' | b'(' => depth += 1,
            b']' | b')' => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    src.len()
}

/// The end of the statement's right-hand side that starts at `from`: the `;` at depth 0.
fn statement_end(src: &[u8], from: usize) -> usize {
    let mut depth = 0i32;
    let mut i = from;
    while i < src.len() {
        match src[i] {
            b'[' | b'(' => depth += 1,
            b']' | b')' => depth -= 1,
            b';' if depth == 0 => return i,
            _ => {}
        }
        i += 1;
    }
    src.len()
}

/// `src` with `NAME[i]` read as `NAME_get(i)` and `NAME[i] = v` / `NAME[i] op= v` written as
/// `NAME_put(i, ...)`, for each name of `names`; comments are copied as they are.
fn accesses(src: &str, names: &[&str]) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    let mut copied = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            i = src[i..].find('\n').map_or(b.len(), |n| i + n);
            continue;
        }
        let starts = is_ident(b[i]) && (i == 0 || !is_ident(b[i - 1]));
        if !starts {
            i += 1;
            continue;
        }
        let mut end = i;
        while end < b.len() && is_ident(b[end]) {
            end += 1;
        }
        let word = &src[i..end];
        if end >= b.len() || b[end] != b'[' || !names.contains(&word) {
            i = end;
            continue;
        }
        out.push_str(&src[copied..i]);
        let shut = close(b, end);
        let index = accesses(&src[end + 1..shut - 1], names);
        let mut k = shut;
        while k < b.len() && (b[k] == b' ' || b[k] == b'\t') {
            k += 1;
        }
        let op = if b.get(k) == Some(&b'=') && b.get(k + 1) != Some(&b'=') {
            Some((None, k + 1))
        } else if matches!(b.get(k), Some(b'+' | b'-' | b'*' | b'/')) && b.get(k + 1) == Some(&b'=')
        {
            Some((Some(b[k] as char), k + 2))
        } else {
            None
        };
        match op {
            Some((compound, from)) => {
                let stop = statement_end(b, from);
                let rhs = accesses(src[from..stop].trim(), names);
                let value = match compound {
                    None => rhs,
                    Some(o) => format!("{word}_get({index}) {o} ({rhs})"),
                };
                out.push_str(&format!("{word}_put({index}, {value})"));
                i = stop;
            }
            None => {
                out.push_str(&format!("{word}_get({index})"));
                i = shut;
            }
        }
        copied = i;
    }
    out.push_str(&src[copied..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(name: &str, binding: u32, read_only: bool, chunks: usize) -> Split {
        Split {
            decl: Decl {
                binding,
                name: name.into(),
                ty: "f64".into(),
                read_only,
            },
            len: 32,
            chunks: (0..chunks)
                .map(|c| {
                    (
                        if c == 0 { binding } else { 40 + c as u32 },
                        256 * c as u64,
                        256,
                    )
                })
                .collect(),
        }
    }

    #[test]
    fn reads_and_writes_go_through_the_accessors() {
        let src = "@group(0) @binding(3) var<storage, read_write> sig: array<f64>;\n\
                   fn f(e: u32) {\n\
                   \x20   let a = sig[ek(e, 2u)] + xsig[e];\n\
                   \x20   sig[e + 1u] = sig[u32(par[e])] * 2.0; // sig[e] = 0\n\
                   \x20   sig[e] += a;\n\
                   \x20   if sig[e] == a { sig[sig_i[e]] = 1.0; }\n\
                   }\n";
        let out = rewrite(src, &[split("sig", 3, false, 3)]);
        assert!(out.contains("@group(0) @binding(41) var<storage, read_write> sig_1: array<f64>;"));
        assert!(out.contains("@group(0) @binding(42) var<storage, read_write> sig_2: array<f64>;"));
        assert!(out.contains("let a = sig_get(ek(e, 2u)) + xsig[e];"));
        assert!(out.contains("sig_put(e + 1u, sig_get(u32(par[e])) * 2.0); // sig[e] = 0"));
        assert!(out.contains("sig_put(e, sig_get(e) + (a));"));
        assert!(out.contains("if sig_get(e) == a { sig_put(sig_i[e], 1.0); }"));
        assert!(out.contains("fn sig_get(i: u32) -> f64 {"));
        assert!(out.contains("case 1u: { return sig_1[j]; }"));
        assert!(out.contains("default: { sig_2[j] = val; }"));
        // nothing else touched
        assert_eq!(rewrite(src, &[]), src);
    }

    #[test]
    fn a_read_only_array_gets_no_store() {
        let out = rewrite(
            "@group(0) @binding(2) var<storage, read> par: array<f64>;\nlet p = par[1u];\n",
            &[split("par", 2, true, 2)],
        );
        assert!(out.contains("var<storage, read> par_1: array<f64>;"));
        assert!(out.contains("let p = par_get(1u);"));
        assert!(!out.contains("par_put"));
    }

    #[test]
    fn declarations_are_found() {
        let src = "@group(0) @binding(1) var<storage, read_write> cu: array<atomic<u32>>;\n\
                   @group(0) @binding(2) var<storage, read> par: array<f64>;\n\
                   @group(0) @binding(3) var<storage, read_write> conn: array<u32>;\n\
                   @group(0) @binding(28) var<uniform> prm: Params;\n";
        let d = declarations(src);
        assert_eq!(d.len(), 2);
        assert_eq!(
            (
                d[0].binding,
                d[0].name.as_str(),
                d[0].ty.as_str(),
                d[0].read_only
            ),
            (2, "par", "f64", true)
        );
        assert_eq!(
            (
                d[1].binding,
                d[1].name.as_str(),
                d[1].ty.as_str(),
                d[1].read_only
            ),
            (3, "conn", "u32", false)
        );
    }

    /// The step's shader with every array that can be split split in three parts: naga (the
    /// WGSL front end wgpu compiles with) parses and validates it, so no access of any array
    /// is left that the accessors do not take (the GPU tests run it split one array at a time,
    /// as lavapipe binds only 32 arrays).
    #[test]
    fn the_step_validates_with_every_array_split() {
        use wgpu::naga;
        let src = crate::contact::step_prefix(true).to_string()
            + "const HAS_RIGID: bool = true;\nconst HAS_TET: bool = true;\n\
                   const HAS_SRI: bool = true;\nconst HAS_EROSION: bool = true;\n\
                   const LAWS: u32 = 15u;\nconst WALL_VALUES: u32 = 8u;\n"
            + include_str!("math.wgsl")
            + include_str!("step.wgsl");
        let decls = declarations(&src);
        assert!(decls.len() >= 28, "{} arrays found", decls.len());
        let mut next = 40;
        let splits: Vec<Split> = (decls.iter())
            .map(|d| plan(d, 3 * 256, 256, 256, &mut next).unwrap())
            .collect();
        let out = rewrite(&src, &splits);
        let module = match naga::front::wgsl::parse_str(&out) {
            Ok(m) => m,
            Err(e) => panic!("{}", e.emit_to_string(&out)),
        };
        let mut v = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::FLOAT64,
        );
        if let Err(e) = v.validate(&module) {
            panic!("{}", e.emit_to_string(&out));
        }
        // every access goes through the accessors: outside comments, a split array is indexed
        // only inside them (once to read, once more to write)
        let code: String = (out.lines())
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n");
        let b = code.as_bytes();
        for d in &decls {
            let pat = format!("{}[", d.name);
            let direct = (code.match_indices(&pat))
                .filter(|&(i, _)| i == 0 || !is_ident(b[i - 1]))
                .count();
            let inside = if d.read_only { 1 } else { 2 };
            assert_eq!(direct, inside, "{}: indexed outside its accessors", d.name);
        }
    }

    #[test]
    fn chunks_bind_and_stay_aligned() {
        let mut next = 40;
        let d = split("sig", 3, false, 1).decl;
        assert_eq!(plan(&d, 1000, 1000, 256, &mut next), None);
        // 1000 bytes of f64 under a 300-byte limit, offsets aligned to 256: chunks of 256 bytes
        let Split { len, chunks, .. } = plan(&d, 1000, 300, 256, &mut next).unwrap();
        assert_eq!(len, 32);
        assert_eq!(
            chunks,
            vec![(3, 0, 256), (40, 256, 256), (41, 512, 256), (42, 768, 232)]
        );
        assert_eq!(next, 43);
        // every value in exactly one chunk
        let total: u64 = chunks.iter().map(|c| c.2).sum();
        assert_eq!(total, 1000);
    }
}
