//! Bounding volume hierarchies: the acceleration structure behind every
//! ray query. [`Bvh`] is an eight-wide BVH over a list of boxes, built with
//! the binned surface area heuristic and traversed with SIMD box tests; it
//! knows nothing of what the boxes hold. Meshes build one over their
//! triangles (`MeshBvh`, in the shapes layer above) and the scene one over
//! its placed primitives (`BvhAggregate`, in the primitive layer).
//! [`LightBuffer`] is the shadow-ray accelerator of scenes with few
//! primitives: per point light, the primitives each direction may meet.

mod bvh;
mod light_buffer;
mod pages;

pub use crate::geometry::traversal_isa;
pub(crate) use pages::{PageArray, ZeroIsValid};

pub use bvh::{BoxRay, Bvh, BvhNode, MAX_LEAF_SIZE, WIDTH};
pub use light_buffer::LightBuffer;
