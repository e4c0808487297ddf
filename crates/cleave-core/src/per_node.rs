//! Per-node data of a model that the copies of a split node share.
//!
//! Splitting gives each element of a separation group nodes of its own: a deck node inside a
//! fully split block gets 8 copies (the paper's split mesh). The copies start as one: the same
//! reference position, initial velocity and deck id. Stored per copy, these would take
//! `24 + 24 + 8 = 56` bytes for each of them: 8.8 MB for the 157,464 copies of a split block of
//! 19,683 elements (`cleave bench cube --elements 20000 --separation`), over a quarter of the
//! 31 MB separation added to that run (43.0 against 12.3 MB before; 35.7 MB since). So a split model keeps them once per deck node,
//! with the deck node of each copy (`origin`, 4 bytes per copy, shared by the three fields).
//!
//! Reading goes through the origin: `values[origin[i]]`. Writing (only model builders and tests
//! write, never the solver) first gives every node its own value, so a write to one copy never
//! changes another.

use std::ops::{Index, IndexMut};
use std::sync::Arc;

/// Values of each node of a model, held once per deck node when the model is split.
#[derive(Clone, Debug, Default)]
pub struct PerNode<T> {
    /// One per node, or one per deck node when `origin` is set.
    values: Vec<T>,
    /// The deck node (index into `values`) of each node of a split model.
    origin: Option<Arc<[u32]>>,
}

impl<T> PerNode<T> {
    /// Node `i` of a split model takes `values[origin[i]]`. Every entry of `origin` must index
    /// `values`.
    pub fn shared(values: Vec<T>, origin: Arc<[u32]>) -> Self {
        assert!(
            origin.iter().all(|&o| (o as usize) < values.len()),
            "origin beyond the deck's nodes"
        );
        Self {
            values,
            origin: Some(origin),
        }
    }

    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.origin.as_ref().map_or(self.values.len(), |o| o.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The value of every node, in node order.
    pub fn iter(&self) -> Iter<'_, T> {
        Iter {
            nodes: self,
            next: 0,
            end: self.len(),
        }
    }

    /// Whether the values are held once per deck node.
    pub fn is_shared(&self) -> bool {
        self.origin.is_some()
    }

    /// The deck node of each node of a split model (`None`: the values are per node, as in a
    /// model not split, or a split model written to since).
    pub fn origin(&self) -> Option<&[u32]> {
        self.origin.as_deref()
    }

    /// The same, shared: a holder of it keeps no copy.
    pub fn origin_shared(&self) -> Option<Arc<[u32]>> {
        self.origin.clone()
    }
}

impl<T: Clone> PerNode<T> {
    /// A vector of every node's value.
    pub fn to_vec(&self) -> Vec<T> {
        self.iter().cloned().collect()
    }

    /// The values, one per node (a split model's copies get values of their own first).
    pub fn as_mut_slice(&mut self) -> &mut [T] {
        self.unshare();
        &mut self.values
    }

    pub fn iter_mut(&mut self) -> std::slice::IterMut<'_, T> {
        self.as_mut_slice().iter_mut()
    }

    pub fn push(&mut self, v: T) {
        self.unshare();
        self.values.push(v);
    }

    pub fn resize(&mut self, n: usize, v: T) {
        self.unshare();
        self.values.resize(n, v);
    }

    pub fn clear(&mut self) {
        self.values.clear();
        self.origin = None;
    }

    /// Give every node a value of its own.
    fn unshare(&mut self) {
        if self.origin.is_some() {
            self.values = self.to_vec();
            self.origin = None;
        }
    }
}

impl<T> Index<usize> for PerNode<T> {
    type Output = T;
    #[inline]
    fn index(&self, i: usize) -> &T {
        match &self.origin {
            None => &self.values[i],
            Some(o) => &self.values[o[i] as usize],
        }
    }
}

impl<T: Clone> IndexMut<usize> for PerNode<T> {
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.as_mut_slice()[i]
    }
}

impl<T> From<Vec<T>> for PerNode<T> {
    fn from(values: Vec<T>) -> Self {
        Self {
            values,
            origin: None,
        }
    }
}

impl<T> FromIterator<T> for PerNode<T> {
    fn from_iter<I: IntoIterator<Item = T>>(it: I) -> Self {
        Vec::from_iter(it).into()
    }
}

impl<T: Clone> Extend<T> for PerNode<T> {
    fn extend<I: IntoIterator<Item = T>>(&mut self, it: I) {
        self.unshare();
        self.values.extend(it);
    }
}

/// The value of each node in turn ([`PerNode::iter`]).
#[derive(Clone, Debug)]
pub struct Iter<'a, T> {
    nodes: &'a PerNode<T>,
    next: usize,
    end: usize,
}

impl<'a, T> Iterator for Iter<'a, T> {
    type Item = &'a T;
    #[inline]
    fn next(&mut self) -> Option<&'a T> {
        (self.next < self.end).then(|| {
            self.next += 1;
            &self.nodes[self.next - 1]
        })
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.end - self.next, Some(self.end - self.next))
    }
}

impl<T> ExactSizeIterator for Iter<'_, T> {}

impl<'a, T: Clone> IntoIterator for &'a PerNode<T> {
    type Item = &'a T;
    type IntoIter = Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a, T: Clone> IntoIterator for &'a mut PerNode<T> {
    type Item = &'a mut T;
    type IntoIter = std::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}

/// Equal when every node has an equal value, however they are held.
impl<T: Clone + PartialEq> PartialEq for PerNode<T> {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<T: Clone + PartialEq> PartialEq<Vec<T>> for PerNode<T> {
    fn eq(&self, other: &Vec<T>) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_read_their_deck_node_and_writes_stay_their_own() {
        let origin: Arc<[u32]> = vec![0, 0, 1, 2, 1].into();
        let mut p = PerNode::shared(vec![10, 20, 30], origin);
        assert_eq!(p.len(), 5);
        assert_eq!(p.to_vec(), vec![10, 10, 20, 30, 20]);
        assert!(p.is_shared());
        assert_eq!(p, PerNode::from(vec![10, 10, 20, 30, 20]));
        p[1] = 11;
        assert!(!p.is_shared());
        assert_eq!(p, vec![10, 11, 20, 30, 20]);
        p.push(40);
        assert_eq!(p.len(), 6);
    }

    #[test]
    #[should_panic(expected = "origin beyond")]
    fn an_origin_beyond_the_values_is_refused() {
        let _ = PerNode::shared(vec![1.0], vec![0, 1].into());
    }
}
