//! Element separation without remeshing (Gerken, Bennett and Smith 2003, section 3).
//!
//! - [`split`]: preprocessing, once: every element of a separation group gets 8 nodes of its
//!   own; the interface table lists every face shared by two elements where at least one is in
//!   a group (the paper's 2 x N element and 8 x N node arrays), with its reference area and
//!   strength ([`strength`]: drawn once per interface from its group's distribution).
//! - [`coincident`]: the coincident node sets tied by intact interfaces, which share one
//!   acceleration a = sum f / sum m; a set splits only where an interface fails.
//! - [`criteria`]: the failure criteria (one file each), [`cohesive`]: the MODEL 3 and 4 laws.
//! - [`interfaces`]: the run-time status of every interface, the failure check, cohesive
//!   forces; [`fragments`]: the components that hold together, with mass, centroid, velocity.

pub mod cohesive;
pub mod coincident;
pub mod criteria;
pub mod fragments;
pub mod interfaces;
pub mod split;
pub mod strength;
