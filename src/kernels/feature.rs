//! Which part of a triangle a closest point lies on.

use crate::math::Real;

/// A feature of a triangle `[v0, v1, v2]`. Edge `i` joins `v_i` and
/// `v_{(i+1) mod 3}`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Feature {
    /// Vertex `i`.
    Vertex(u8),
    /// Edge `i`, from vertex `i` to vertex `(i + 1) mod 3`, excluding its ends.
    Edge(u8),
    /// The interior of the face.
    Face,
}

/// In words, as files and messages write it: `vertex 0`, `edge 2`, `face`.
impl std::fmt::Display for Feature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Feature::Vertex(i) => write!(f, "vertex {i}"),
            Feature::Edge(i) => write!(f, "edge {i}"),
            Feature::Face => f.write_str("face"),
        }
    }
}

impl Feature {
    /// The feature of edge `edge` at parameter `s` (0 at its first vertex).
    #[inline]
    pub fn on_edge(edge: u8, s: Real) -> Feature {
        if s <= 0.0 {
            Feature::Vertex(edge)
        } else if s >= 1.0 {
            Feature::Vertex((edge + 1) % 3)
        } else {
            Feature::Edge(edge)
        }
    }
}
