//! The node layout: eight children per node, their boxes stored one array
//! per coordinate so that a node's box tests are four-lane SIMD passes.

use crate::accel::pages::ZeroIsValid;
use crate::geometry::{Bounds3, Vec3};
use glam::Vec4;

/// Children per node.
pub const WIDTH: usize = 8;
/// Groups of four children, tested one group per pass of four-lane SIMD.
pub(super) const GROUPS: usize = WIDTH / 4;

/// A node with up to [`WIDTH`] children: their boxes in structure-of-arrays
/// form, and for each child either the index of its node or, for a leaf,
/// its range of primitives. 256 bytes, four cache lines.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct BvhNode {
    /// The six slab planes of the children's boxes: `planes[axis][group]`
    /// holds the lower corners' coordinate `axis` for children
    /// `4·group .. 4·group + 4`, and `planes[3 + axis][group]` the upper
    /// corners'. One array, so that a ray's near and far planes are two
    /// indices into it (`BoxRay`).
    pub planes: [[Vec4; GROUPS]; 6],
    /// Node index of an interior child, first primitive slot of a leaf.
    pub child: [u32; WIDTH],
    /// Number of primitives of a leaf child; 0 for an interior child or an
    /// empty slot (whose box is empty, so it is never entered).
    pub count: [u32; WIDTH],
}

// SAFETY: a node is floats and integers only.
unsafe impl ZeroIsValid for BvhNode {}

pub(super) const EMPTY_NODE: BvhNode = BvhNode {
    planes: [
        [Vec4::INFINITY; GROUPS],
        [Vec4::INFINITY; GROUPS],
        [Vec4::INFINITY; GROUPS],
        [Vec4::NEG_INFINITY; GROUPS],
        [Vec4::NEG_INFINITY; GROUPS],
        [Vec4::NEG_INFINITY; GROUPS],
    ],
    child: [0; WIDTH],
    count: [0; WIDTH],
};

/// Most primitives a leaf may hold.
pub const MAX_LEAF_SIZE: usize = 4;

/// Cache lines of a node.
pub(super) const NODE_LINES: usize = std::mem::size_of::<BvhNode>() / 64;

impl BvhNode {
    /// The box of child `slot` (empty for an unused slot).
    pub fn child_bounds(&self, slot: usize) -> Bounds3 {
        let (g, l) = (slot / 4, slot % 4);
        Bounds3 {
            min: Vec3::new(self.planes[0][g][l], self.planes[1][g][l], self.planes[2][g][l]),
            max: Vec3::new(self.planes[3][g][l], self.planes[4][g][l], self.planes[5][g][l]),
        }
    }

    pub(super) fn set_child_bounds(&mut self, slot: usize, b: &Bounds3) {
        let (g, l) = (slot / 4, slot % 4);
        for axis in 0..3 {
            self.planes[axis][g][l] = b.min[axis];
            self.planes[3 + axis][g][l] = b.max[axis];
        }
    }
}
