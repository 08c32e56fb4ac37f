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
mod simd;

pub(crate) use pages::{PageArray, ZeroIsValid};
#[cfg(all(test, target_arch = "x86_64"))]
pub(crate) use simd::detect as simd_detected;
pub(crate) use simd::isa;
pub use simd::traversal_isa;
#[cfg(target_arch = "x86_64")]
pub(crate) use simd::Isa;

pub use bvh::{BoxRay, Bvh, BvhNode, MAX_LEAF_SIZE, WIDTH};
pub use light_buffer::LightBuffer;
