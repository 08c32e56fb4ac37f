//! Merging loose triangles into meshes before the top-level BVH is built.

use super::{Primitive, NO_LIGHT};
use crate::geometry::Transform;
use crate::material::MaterialId;
use crate::mesh::TriangleMesh;
use crate::shapes::{Mesh, Shape};
use std::sync::Arc;

/// The fewest loose triangles of one kind (flat or smooth) that are merged
/// into a mesh. Fewer stay single primitives: then each is one child box in
/// a node of the top-level BVH, one box test that the ray pays there anyway,
/// and one triangle test behind it; as a mesh they would cost a second
/// traversal (its own root node) on every ray that reaches the mesh's box.
/// Eight is a node's width: up to eight children share one four-lane pair
/// of box tests. (The showcase's two triangles, one flat and one smooth,
/// were two one-triangle meshes: keeping them single cut its instructions
/// by 6%, callgrind at 200×150 and 4 spp.)
pub(crate) const MIN_MERGED_TRIANGLES: usize = 8;

/// `primitives` with every loose triangle (a [`Shape::Triangle`] primitive)
/// moved into a world-space [`Mesh`]: one for the flat triangles, one for
/// the smooth ones (with per-vertex normals, carried through the inverse
/// transpose of each triangle's transform). Each face keeps its triangle's
/// material (through the mesh's material ids and
/// [`Primitive::with_face_materials`]) and area light (through a per-face
/// light table), and its texture coordinates, the barycentrics `(b₁, b₂)`.
/// Other primitives are returned as they are. A group of fewer than
/// [`MIN_MERGED_TRIANGLES`], or one whose mesh cannot be built, stays as it
/// is.
pub(crate) fn merge_loose_triangles(primitives: &[Primitive]) -> Vec<Primitive> {
    // Triangles with an alpha cut-out keep their own primitive (and
    // texture), reversed ones their flag, medium boundaries their media.
    let loose = |p: &Primitive| {
        matches!(p.shape(), Shape::Triangle(_))
            && p.alpha().is_none()
            && !p.reverse_orientation()
            && p.media() == crate::medium::MediumInterface::NONE
    };
    if primitives.iter().filter(|p| loose(p)).count() < MIN_MERGED_TRIANGLES {
        return primitives.to_vec();
    }
    let mut out: Vec<Primitive> = primitives.iter().filter(|p| !loose(p)).cloned().collect();
    for smooth in [false, true] {
        let group: Vec<&Primitive> = primitives
            .iter()
            .filter(|p| loose(p) && matches!(p.shape(), Shape::Triangle(t) if t.normals().is_some() == smooth))
            .collect();
        if group.len() < MIN_MERGED_TRIANGLES {
            out.extend(group.into_iter().cloned());
            continue;
        }
        let mut mesh = TriangleMesh::default();
        let mut normals = Vec::new();
        let mut table: Vec<MaterialId> = Vec::new();
        let mut material_ids = Vec::with_capacity(group.len());
        let mut lights = Vec::with_capacity(group.len());
        for prim in &group {
            let Shape::Triangle(tri) = prim.shape() else { unreachable!() };
            let t = prim.transform();
            let identity = t.is_identity();
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(tri.vertices().map(|p| if identity { p } else { t.point(p) }));
            if let Some(ns) = tri.normals() {
                normals.extend(ns.map(|n| if identity { n } else { t.normal(n).normalize_or_zero() }));
            }
            mesh.indices.push([base, base + 1, base + 2]);
            let m = prim.material();
            let index = table.iter().position(|&x| x == m).unwrap_or_else(|| {
                table.push(m);
                table.len() - 1
            });
            material_ids.push(index as u32);
            lights.push(prim.area_light().unwrap_or(NO_LIGHT));
        }
        if smooth {
            mesh.normals = Some(normals);
        }
        mesh.material_ids = Some(material_ids);
        match Mesh::new(mesh) {
            Ok(mesh) if mesh.degenerate_count() == 0 => {
                let mut merged =
                    Primitive::new(Arc::new(mesh), Transform::IDENTITY, table[0]).with_face_materials(table.into());
                if lights.iter().any(|&l| l != NO_LIGHT) {
                    merged = merged.with_face_lights(lights.into());
                }
                out.push(merged);
            }
            // Degenerate once transformed, or not finite: leave them be.
            _ => out.extend(group.into_iter().cloned()),
        }
    }
    out
}

#[cfg(test)]
mod merge_tests {
    use super::*;
    use crate::geometry::{Ray, Vec3};
    use crate::primitive::{Aggregate, BvhAggregate, LinearAggregate};
    use crate::sampling::Pcg32;
    use crate::shapes::{Sphere, Triangle};

    /// Merging loose triangles into meshes must not change what a ray
    /// hits: the same surface, material, area light, normals and
    /// texture coordinates as the triangles tested one by one.
    #[test]
    fn merged_triangles_hit_like_the_loose_ones() {
        let m: Vec<MaterialId> = (0..3).map(MaterialId::new).collect();
        let mut primitives = Vec::new();
        let mut lights = 0;
        let mut rng = Pcg32::new(3, 5);
        let mut v = |s: f32| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * s;
        for i in 0..40 {
            let c = v(4.0);
            let p = [c + v(1.5), c + v(1.5), c + v(1.5)];
            let normals = (i % 3 == 0).then(|| [v(1.0) + Vec3::Z, v(1.0) + Vec3::Z, v(1.0) + Vec3::Z]);
            let t = if i % 4 == 1 { Transform::translate(v(1.0)) } else { Transform::rotate_y(37.0 * i as f32) };
            let prim = Primitive::new(Triangle::new(p, normals).unwrap(), t, m[i % 3]);
            if i % 5 == 2 {
                primitives.push(prim.with_area_light(lights));
                lights += 1;
            } else {
                primitives.push(prim);
            }
        }
        primitives.push(Primitive::new(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.7).unwrap(), Transform::IDENTITY, m[1]));
        let merged = merge_loose_triangles(&primitives);
        assert_eq!(merged.len(), 3, "a sphere, a flat mesh and a smooth mesh");
        let bvh = BvhAggregate::new(&merged);
        let list = LinearAggregate::new(primitives);
        let mut rng = Pcg32::new(8, 1);
        let (mut hits, mut lit) = (0, 0);
        for _ in 0..20_000 {
            let o = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 10.0;
            let d = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
            let ray = Ray::new(o, d);
            let (a, b) = (bvh.intersect(&ray, f32::INFINITY), list.intersect(&ray, f32::INFINITY));
            assert_eq!(bvh.intersect_p(&ray, 6.0), list.intersect_p(&ray, 6.0));
            let (Some(a), Some(b)) = (a, b) else {
                assert_eq!(a.is_some(), b.is_some(), "ray {ray:?}");
                continue;
            };
            hits += 1;
            assert!((a.t - b.t).abs() <= 1e-4 * b.t.max(1.0), "{} vs {}", a.t, b.t);
            assert_eq!(a.material, b.material);
            assert_eq!(a.light, b.light);
            lit += a.light.is_some() as u32;
            assert!((a.n - b.n).length() < 1e-3 && (a.ns - b.ns).length() < 1e-3, "{a:?} vs {b:?}");
            assert!((a.uv - b.uv).length() < 1e-3, "{a:?} vs {b:?}");
        }
        assert!(hits > 500 && lit > 50, "{hits} hits, {lit} on lights");
    }

    /// Fewer than eight triangles of a kind stay single primitives; the
    /// other kind is merged on its own count.
    #[test]
    fn a_few_triangles_of_a_kind_stay_loose() {
        let m = MaterialId::new(0);
        let tri = |i: usize, smooth: bool| {
            let c = Vec3::new(i as f32, 0.0, 0.0);
            let normals = smooth.then_some([Vec3::Z; 3]);
            Primitive::new(Triangle::new([c, c + Vec3::X, c + Vec3::Y], normals).unwrap(), Transform::IDENTITY, m)
        };
        let count = |prims: &[Primitive]| {
            let loose = prims.iter().filter(|p| matches!(p.shape(), Shape::Triangle(_))).count();
            let meshes = prims.iter().filter(|p| matches!(p.shape(), Shape::Mesh(_))).count();
            (loose, meshes)
        };
        // One flat and one smooth triangle (the showcase): both stay.
        assert_eq!(count(&merge_loose_triangles(&[tri(0, false), tri(1, true)])), (2, 0));
        // Seven flat and eight smooth: the flat stay, the smooth become a mesh.
        let prims: Vec<Primitive> = (0..7).map(|i| tri(i, false)).chain((0..8).map(|i| tri(i, true))).collect();
        assert_eq!(count(&merge_loose_triangles(&prims)), (7, 1));
        assert_eq!(MIN_MERGED_TRIANGLES, 8);
    }
}
