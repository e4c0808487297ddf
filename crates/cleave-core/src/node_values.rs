//! Values of every node of a model, read through the slots of its coincident sets.
//!
//! A split model's copies of a deck node move as one while they are tied (the paper's
//! equations 1-4: one acceleration `sum f / sum m` per coincident set), so the solver keeps
//! their positions and velocities once per set, in the set's *slot*
//! ([`crate::separation::coincident::CoincidentSets::slots`]), not once per copy: on the
//! 20,000-element ball the 160,072 copies start in 21,343 slots. [`NodeValues`] reads them by
//! node, `values[slot[i]]`, so the contact, the interface checks and the output index by node
//! as they would a plain array. Without separation (or when a rigid body is bonded to a group:
//! its node must follow the body while the copies tied to it follow the set, so every copy
//! keeps its own entry) there is no slot map and node i reads `values[i]`.

use std::ops::Index;

/// Per-node values, stored once per slot (`values[slot[i]]`) or once per node.
#[derive(Debug)]
pub struct NodeValues<'a, T> {
    values: &'a [T],
    slot: Option<&'a [u32]>,
}

impl<T> Clone for NodeValues<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for NodeValues<'_, T> {}

impl<'a, T> NodeValues<'a, T> {
    /// Node i reads `values[slot[i]]` (every entry of `slot` must index `values`), or
    /// `values[i]` without a slot map.
    pub fn new(values: &'a [T], slot: Option<&'a [u32]>) -> Self {
        Self { values, slot }
    }

    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.slot.map_or(self.values.len(), |s| s.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The entry that holds node i's value: `slot[i]`, or i without a slot map.
    #[inline]
    pub fn entry_of(&self, i: usize) -> usize {
        match self.slot {
            Some(s) => s[i] as usize,
            None => i,
        }
    }

    /// The value of node i.
    #[inline]
    pub fn get(&self, i: usize) -> &'a T {
        &self.values[self.entry_of(i)]
    }

    /// Every node's value, in node order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &'a T> + 'a {
        let me = *self;
        (0..self.len()).map(move |i| me.get(i))
    }

    /// The stored entries (one per slot, or per node).
    pub fn entries(&self) -> &'a [T] {
        self.values
    }

    /// The slot of each node, if the values are stored per slot.
    pub fn slots(&self) -> Option<&'a [u32]> {
        self.slot
    }

    /// Other values stored the same way (one entry per slot of the same map, or per node).
    pub fn over<'b, U>(&self, values: &'b [U]) -> NodeValues<'b, U>
    where
        'a: 'b,
    {
        NodeValues::new(values, self.slot)
    }
}

impl<T: Clone> NodeValues<'_, T> {
    /// A vector of every node's value.
    pub fn to_vec(&self) -> Vec<T> {
        self.iter().cloned().collect()
    }
}

impl<'a, T> From<&'a [T]> for NodeValues<'a, T> {
    fn from(values: &'a [T]) -> Self {
        Self::new(values, None)
    }
}

impl<'a, T> From<&'a Vec<T>> for NodeValues<'a, T> {
    fn from(values: &'a Vec<T>) -> Self {
        Self::new(values, None)
    }
}

impl<T> Index<usize> for NodeValues<'_, T> {
    type Output = T;
    #[inline]
    fn index(&self, i: usize) -> &T {
        self.get(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_through_the_slots() {
        let values = [10, 20, 30];
        let slot = [0, 2, 2, 1];
        let v = NodeValues::new(&values[..], Some(&slot[..]));
        assert_eq!(v.len(), 4);
        assert_eq!(v.to_vec(), vec![10, 30, 30, 20]);
        assert_eq!(v[3], 20);
        let plain = NodeValues::from(&values[..]);
        assert_eq!(plain.len(), 3);
        assert_eq!(plain.to_vec(), vec![10, 20, 30]);
    }
}
