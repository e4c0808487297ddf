//! Lists by entry: a counting sort into one array with a start per entry.

/// Values listed by entry (`n` entries), each entry's in the order given: a counting sort.
pub(crate) struct ByEntry {
    start: Vec<u32>,
    values: Vec<u32>,
}

impl ByEntry {
    pub fn new(n: usize, items: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        let mut start = vec![0u32; n + 1];
        for (e, _) in items.clone() {
            start[e as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut values = vec![0; start[n] as usize];
        for (e, v) in items {
            values[fill[e as usize] as usize] = v;
            fill[e as usize] += 1;
        }
        ByEntry { start, values }
    }

    pub fn of(&self, e: u32) -> &[u32] {
        &self.values[self.start[e as usize] as usize..self.start[e as usize + 1] as usize]
    }
}
