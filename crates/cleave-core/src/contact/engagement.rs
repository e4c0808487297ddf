//! How much of a node's penetration carries force: the penalty spring starts where the node's
//! motion says contact began, and keeps its energy when the node changes face.
//!
//! A node-to-face penalty `f = -k g n` is conservative only while the node stays on one face
//! and enters it from outside. Two events break that, and both inject energy that no force
//! did work for:
//! - **Late detection.** The node is found deeper than one step's approach could take it: it
//!   slid over a convex edge of the other body, or the face joined the surface when an
//!   interface failed under compression, at the corner where several fragments meet. The full
//!   `k |g|` would appear at once, with energy `1/2 k g^2` from nowhere.
//! - **Face change.** At a corner the nearest face changes: the spring jumps from `k_a g_a` to
//!   `k_b g_b`.
//!
//! The rule (in the spirit of LS-DYNA's tracking of initial penetrations, IGNORE = 1, applied
//! to every engagement): the force is `-k e n` with the *engaged* penetration
//! `e = g - o <= 0`, where the offset `o <= 0` is set when the pair engages and follows the node
//! out (`o <- max(o, g)`):
//! - entering contact: `e = max(g, -a)`, with `a = max(0, -v_rel.n) dt` the approach over the
//!   last step (a node that crossed the surface within the step is fully engaged; one found
//!   deeper starts with the part its motion explains);
//! - same face as the last step: `o <- max(o, g)`;
//! - another face: the spring energy is carried over,
//!   `e = max(g, e_prev sqrt(k_prev / k) - a)`.
//!
//! For a genuine contact (the node arrives from outside), `o = 0` and nothing changes. A
//! node that was detected late keeps a residual penetration `o` until it moves out of it. At
//! the first step of a run there is no motion yet (`a` infinite): penetrations of the deck's
//! geometry are engaged in full and pushed out.

/// The engaged state of a node on a face after this step.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Engagement {
    /// Engaged penetration e = g - o (<= 0); the force is `-k e n`.
    pub engaged: f64,
    /// Offset o (<= 0) kept for the next step.
    pub offset: f64,
}

/// What the node had last step.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub enum Previous {
    /// Not in contact.
    Free,
    /// On the same face, with this offset.
    Same { offset: f64 },
    /// On another face, with its stiffness and engaged penetration.
    Other { k: f64, engaged: f64 },
}

/// The engaged penetration of a node at gap `gap` (< 0) on a face of stiffness `k`, after
/// `prev`, having approached the face by `approach` (>= 0) over the last step.
#[inline]
pub fn engage(prev: Previous, k: f64, gap: f64, approach: f64) -> Engagement {
    let engaged = match prev {
        Previous::Free => gap.max(-approach),
        Previous::Same { offset } => gap - offset.max(gap),
        Previous::Other {
            k: k_prev,
            engaged: e_prev,
        } => {
            let carried = if k > 0.0 {
                e_prev * (k_prev / k).sqrt()
            } else {
                0.0
            };
            gap.max(carried - approach)
        }
    };
    let engaged = engaged.min(0.0);
    Engagement {
        engaged,
        offset: gap - engaged,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_arriving_from_outside_is_fully_engaged() {
        let e = engage(Previous::Free, 1.0, -0.3, 0.5);
        assert_eq!(e.engaged, -0.3);
        assert_eq!(e.offset, 0.0);
    }

    #[test]
    fn a_node_found_deep_starts_with_its_approach_and_keeps_the_rest_as_offset() {
        let e = engage(Previous::Free, 1.0, -2.0, 0.5);
        assert_eq!(e.engaged, -0.5);
        assert_eq!(e.offset, -1.5);
        // deeper next step: the spring grows from there
        let f = engage(Previous::Same { offset: e.offset }, 1.0, -2.2, 0.2);
        assert!((f.engaged + 0.7).abs() < 1e-15);
        // backing out past the offset: no force, the offset follows the node
        let g = engage(Previous::Same { offset: f.offset }, 1.0, -1.0, 0.0);
        assert_eq!(g.engaged, 0.0);
        assert_eq!(g.offset, -1.0);
    }

    #[test]
    fn changing_face_keeps_the_spring_energy() {
        // 1/2 k_a e_a^2 = 1/2 k_b e_b^2 when the new face is penetrated deeply enough
        let e = engage(
            Previous::Other {
                k: 4.0,
                engaged: -0.1,
            },
            1.0,
            -1.0,
            0.0,
        );
        assert!((e.engaged + 0.2).abs() < 1e-15);
        assert!((0.5 * 4.0 * 0.01 - 0.5 * 1.0 * e.engaged * e.engaged).abs() < 1e-15);
        // never more than the penetration of the new face
        let e = engage(
            Previous::Other {
                k: 4.0,
                engaged: -0.1,
            },
            1.0,
            -0.05,
            0.0,
        );
        assert_eq!(e.engaged, -0.05);
        assert_eq!(e.offset, 0.0);
    }
}
