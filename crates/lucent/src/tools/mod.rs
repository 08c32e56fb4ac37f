//! Tools around the renderer, not part of it: comparing images, making
//! procedural skies to light scenes with, and the meshes of the raybench
//! protocol. The `lucent` program and the tests use them; no module of the
//! renderer does (this is the top layer).

pub mod compare;
pub mod raybench;
pub mod readers;
pub mod sky;
pub mod uv_sphere;

pub use compare::{
    block_means, compare, read_image, relative_squared_error, srgb_decode, CompareError, DiffMetrics, ImageReadError,
    REL_MSE_EPSILON,
};
pub use raybench::{load_mesh_list, load_raybench_mesh};
pub use uv_sphere::{uv_sphere, MAX_SPHERE_CELLS};
