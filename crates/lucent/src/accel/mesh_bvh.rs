//! A BVH over the triangles of one mesh, in the mesh's object space: the
//! bottom level of lucent's two-level acceleration structure.

use super::bvh::{BoxRay, Bvh};
use crate::geometry::{Bounds3, Ray, Vec3};
use crate::mesh::TriangleMesh;
use crate::shapes::watertight::{intersect_triangle, WatertightRay};
use rayon::prelude::*;

/// A closest hit on a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Ray parameter.
    pub t: f32,
    /// Index of the triangle in the mesh it was built from.
    pub triangle: u32,
    /// Barycentric weights of the triangle's corners.
    pub b: [f32; 3],
}

/// Triangles in BVH leaf order, with the hierarchy over them.
///
/// The corners are copied out of the index buffer into leaf order (36 bytes
/// a triangle), so a leaf's triangles are contiguous in memory and a test
/// needs no index indirection. Zero-area triangles are left out: no ray can
/// hit them.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    /// The hierarchy; its primitive list gives the original index of each
    /// entry of `triangles`.
    bvh: Bvh,
    triangles: Vec<[Vec3; 3]>,
}

impl MeshBvh {
    /// Build over every triangle of `mesh`, using the current rayon pool.
    pub fn build(mesh: &TriangleMesh) -> Self {
        let bounds: Vec<Bounds3> = (0..mesh.triangle_count())
            .into_par_iter()
            .with_min_len(1024)
            .map(|i| {
                let [a, b, c] = mesh.triangle(i);
                let area2 = (b - a).cross(c - a).length_squared();
                if area2 > 0.0 && area2.is_finite() {
                    Bounds3::from_points(a, b).union_point(c)
                } else {
                    Bounds3::EMPTY
                }
            })
            .collect();
        let bvh = Bvh::build(&bounds);
        let triangles = bvh.primitives().par_iter().with_min_len(1024).map(|&i| mesh.triangle(i as usize)).collect();
        Self { bvh, triangles }
    }

    /// Triangles in the structure (zero-area ones excluded).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Bounds of all triangles in the structure.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// Heap bytes: nodes, triangle copies and index map.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.triangles.capacity() * std::mem::size_of::<[Vec3; 3]>()
    }

    /// The closest hit with `t ∈ [t_min, t_max]`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<MeshHit> {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        let mut t_max = t_max;
        let mut best = None;
        self.bvh.traverse_closest(&box_ray, t_min, &mut t_max, |slot, t_max| {
            match intersect_triangle(&tri_ray, &self.triangles[slot], t_min, *t_max) {
                Some(h) => {
                    *t_max = h.t;
                    best = Some((slot, h));
                    true
                }
                None => false,
            }
        });
        best.map(|(slot, h)| MeshHit { t: h.t, triangle: self.bvh.primitives()[slot], b: h.b })
    }

    /// Whether any triangle is hit with `t ∈ [t_min, t_max]`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let box_ray = BoxRay::new(ray.origin, ray.dir);
        let tri_ray = WatertightRay::new(ray);
        self.bvh.traverse_any(&box_ray, t_min, t_max, |slot| {
            intersect_triangle(&tri_ray, &self.triangles[slot], t_min, t_max).is_some()
        })
    }
}
