//! Keyword text of a box of hexahedra, shared by the tests that write decks.

/// `*NODE` and `*ELEMENT_SOLID` data lines (free format) of an `n[0] x n[1] x n[2]` box of
/// hexahedra of side `h` with its lowest corner at `origin`: node ids from `n0` (x fastest),
/// element ids from `e0`, all in part `pid`.
pub fn hex_block(
    n0: usize,
    e0: usize,
    pid: usize,
    n: [usize; 3],
    h: f64,
    origin: [f64; 3],
) -> (String, String) {
    let id = |i: usize, j: usize, k: usize| n0 + i + (n[0] + 1) * (j + (n[1] + 1) * k);
    let mut nodes = String::new();
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                nodes += &format!(
                    "{}, {}, {}, {}\n",
                    id(i, j, k),
                    origin[0] + h * i as f64,
                    origin[1] + h * j as f64,
                    origin[2] + h * k as f64
                );
            }
        }
    }
    let mut elems = String::new();
    let mut e = e0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                elems += &format!(
                    "{e}, {pid}, {}, {}, {}, {}, {}, {}, {}, {}\n",
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1)
                );
                e += 1;
            }
        }
    }
    (nodes, elems)
}
