//! What the sections of an MSH file hold, as read: before any check across sections (node
//! tags of elements, physical groups of entities), each item with the byte where it starts.

use std::collections::HashMap;

use super::types::ElemType;

/// The MSH format version of a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// MSH 4.1: entities, node and element blocks, physical groups on the entities.
    V41,
    /// MSH 2.2 (2.0 and 2.1 read the same way): one node list, one element list, each element
    /// with its physical and elementary tags.
    V22,
}

/// A node.
#[derive(Clone, Debug)]
pub struct RawNode {
    pub tag: i64,
    pub x: [f64; 3],
    pub pos: usize,
}

/// Which groups an element belongs to, as its format says it.
#[derive(Clone, Debug)]
pub enum Owner {
    /// MSH 4.1: the tag of the entity of its block (of the element's dimension); its physical
    /// groups are the entity's in `$Entities`.
    Entity(i64),
    /// MSH 2.2: the element's first two tags, its physical group (0: none) and its elementary
    /// (geometric) entity, when written.
    Tags {
        physical: i64,
        elementary: Option<i64>,
    },
}

/// An element.
#[derive(Clone, Debug)]
pub struct RawElem {
    pub tag: i64,
    pub ty: ElemType,
    pub owner: Owner,
    pub nodes: Vec<i64>,
    pub pos: usize,
}

/// A physical group's name (`$PhysicalNames`).
#[derive(Clone, Debug)]
pub struct RawName {
    pub dim: u8,
    pub tag: i64,
    pub name: String,
}

/// Everything read from one file.
#[derive(Clone, Debug)]
pub struct RawMsh {
    pub version: Version,
    pub binary: bool,
    pub names: Vec<RawName>,
    /// MSH 4.1 `$Entities`: the physical tags of each (dimension, entity tag); `None` without
    /// the section (then no element is in a physical group).
    pub entities: Option<HashMap<(u8, i64), Vec<i64>>>,
    pub nodes: Vec<RawNode>,
    pub elems: Vec<RawElem>,
}
