//! Merging loose triangles and small meshes into meshes before the
//! top-level BVH is built.

use super::{Primitive, NO_LIGHT};
use crate::geometry::Transform;
use crate::material::MaterialId;
use crate::mesh::TriangleMesh;
use crate::shapes::{DefaultUv, Mesh, Shape};
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

/// The per-face tables of a mesh merged from several primitives: each
/// face's material, as an index into the merged primitive's material table
/// (one entry per distinct material, in the order they come), and its area
/// light or [`NO_LIGHT`].
#[derive(Default)]
struct FaceTables {
    table: Vec<MaterialId>,
    material_ids: Vec<u32>,
    lights: Vec<u32>,
}

impl FaceTables {
    /// Add the next face.
    fn push(&mut self, material: MaterialId, light: Option<u32>) {
        let index = self.table.iter().position(|&x| x == material).unwrap_or_else(|| {
            self.table.push(material);
            self.table.len() - 1
        });
        self.material_ids.push(index as u32);
        self.lights.push(light.unwrap_or(NO_LIGHT));
    }

    /// The merged primitive: `mesh`, whose faces were pushed in order, with
    /// each face's material and area light (a per-face light table only
    /// where some face emits). At least one face must have been pushed.
    fn primitive(self, mesh: Mesh) -> Primitive {
        let merged =
            Primitive::new(Arc::new(mesh), Transform::IDENTITY, self.table[0]).with_face_materials(self.table.into());
        if self.lights.iter().any(|&l| l != NO_LIGHT) {
            merged.with_face_lights(self.lights.into())
        } else {
            merged
        }
    }
}

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
        let mut faces = FaceTables::default();
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
            faces.push(prim.material(), prim.area_light());
        }
        if smooth {
            mesh.normals = Some(normals);
        }
        mesh.material_ids = Some(std::mem::take(&mut faces.material_ids));
        match Mesh::new(mesh) {
            Ok(mesh) if mesh.degenerate_count() == 0 => out.push(faces.primitive(mesh)),
            // Degenerate once transformed, or not finite: leave them be.
            _ => out.extend(group.into_iter().cloned()),
        }
    }
    out
}

/// The most triangles a mesh may have and still be merged with other small
/// meshes ([`merge_small_meshes`]). A mesh is its own BVH under the top
/// level: every ray that reaches its box pays a second traversal's set-up
/// (the ray's box and watertight forms, the root node) before its first
/// triangle test. For a mesh of a few dozen triangles that set-up is most
/// of the mesh's cost, and where the boxes of such meshes overlap (the
/// walls of a room) a ray enters several; whether merging them pays is
/// [`merging_pays`]'s question. Larger meshes amortise the set-up over a
/// deep traversal, and merging would build their BVH a second time.
pub(crate) const MAX_MERGED_MESH_TRIANGLES: usize = 1024;

/// What a mesh's faces carry besides positions and indices: meshes are
/// merged only with meshes that carry the same (a merged mesh has an
/// attribute for all its vertices or for none), so each face's hit record
/// is the one its own mesh gives, bit for bit.
#[derive(Clone, Copy, PartialEq, Eq)]
struct MeshKind {
    normals: bool,
    uvs: bool,
    uvs1: bool,
    colors: bool,
    tangents: bool,
    face_indices: bool,
    default_uv: DefaultUv,
}

impl MeshKind {
    fn of(mesh: &Mesh, data: &TriangleMesh) -> Self {
        Self {
            normals: data.normals.is_some(),
            uvs: data.uvs.is_some(),
            uvs1: data.uvs1.is_some(),
            colors: data.colors.is_some(),
            tangents: data.tangents.is_some(),
            face_indices: data.face_indices.is_some(),
            default_uv: mesh.default_uv(),
        }
    }
}

/// `primitives` with the small meshes (at most
/// [`MAX_MERGED_MESH_TRIANGLES`] triangles; untransformed, without alpha,
/// reversed orientation or media) of each [`MeshKind`] merged into one
/// mesh, when there are two or more of a kind and the surface area
/// heuristic says a ray pays less for the one mesh ([`merging_pays`]; the
/// meshes are kept as they are otherwise). Each face keeps its own
/// material and area light (through [`Primitive::with_face_materials`]
/// and a per-face light table); its positions, normals, texture
/// coordinates and other attributes are copied as stored, so a ray finds
/// the same surface with the same hit record as before. Other primitives
/// are returned as they are.
pub(crate) fn merge_small_meshes(primitives: Vec<Primitive>) -> Vec<Primitive> {
    let small = |p: &Primitive| match p.shape() {
        Shape::Mesh(mesh) => {
            mesh.triangle_count() <= MAX_MERGED_MESH_TRIANGLES
                && p.transform.is_none()
                && p.alpha().is_none()
                && !p.reverse_orientation()
                && p.media() == crate::medium::MediumInterface::NONE
        }
        _ => false,
    };
    if primitives.iter().filter(|p| small(p)).count() < 2 {
        return primitives;
    }
    let (candidates, mut out): (Vec<Primitive>, Vec<Primitive>) = primitives.into_iter().partition(|p| small(p));
    // The meshes' data, grouped by kind in the order they come.
    let mut groups: Vec<(MeshKind, Vec<(Primitive, TriangleMesh)>)> = Vec::new();
    for prim in candidates {
        let Shape::Mesh(mesh) = prim.shape() else { unreachable!("only meshes are candidates") };
        let data = mesh.to_triangle_mesh();
        let kind = MeshKind::of(mesh, &data);
        match groups.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, group)) => group.push((prim, data)),
            None => groups.push((kind, vec![(prim, data)])),
        }
    }
    for (kind, group) in groups {
        if group.len() < 2 {
            out.extend(group.into_iter().map(|(prim, _)| prim));
            continue;
        }
        match merged_mesh(kind, &group) {
            Some(merged) if merging_pays(&merged, &group) => out.push(merged),
            _ => out.extend(group.into_iter().map(|(prim, _)| prim)),
        }
    }
    out
}

/// What entering a mesh from the top level costs a ray, in the units of
/// [`Mesh::expected_cost`] (one box or leaf-block test): the call into the
/// mesh, the ray's set-up for its traversal, and the top-level leaf that
/// holds it. One test's worth; the decision below does not turn on it for
/// the scenes measured (see [`merging_pays`]).
const MESH_ENTRY_COST: f32 = 1.0;

/// Whether one mesh `merged` is cheaper for rays than the meshes of
/// `group` it was merged from, by the surface area heuristic: a ray that
/// enters the merged mesh's box `U` enters part `i`'s box with probability
/// `A(i) / A(U)`, so the parts cost `Σ A(i)/A(U) · (entry + cost(i))` and
/// the merged mesh `entry + cost(U)`, each `cost` the expected cost of a
/// query inside the mesh's own tree ([`Mesh::expected_cost`]).
///
/// The walls of a Cornell box (five quads around the room, two blocks
/// inside it) enter each other's boxes: 4.34 merged against 4.44 + 2.0 ×
/// entry apart, and merging made the scene 6.6% faster. The Veach MIS
/// scene's four thin plates are far apart above a floor and a wall: 1.97
/// merged against 1.80 + 0.87 × entry apart, and merging made it 5% slower
/// (`docs/performance.md`, twenty-seventh sitting). The top level's own
/// nodes, which only the separate meshes need, are left out, so the
/// heuristic merges only where it clearly pays.
fn merging_pays(merged: &Primitive, group: &[(Primitive, TriangleMesh)]) -> bool {
    fn mesh_of(p: &Primitive) -> Option<&Mesh> {
        match p.shape() {
            Shape::Mesh(mesh) => Some(mesh),
            _ => None,
        }
    }
    let Some(whole) = mesh_of(merged) else { return false };
    let area = whole.bounds().surface_area();
    if area <= 0.0 || !area.is_finite() {
        return false;
    }
    let apart: f32 = group
        .iter()
        .filter_map(|(p, _)| mesh_of(p))
        .map(|part| part.bounds().surface_area() / area * (MESH_ENTRY_COST + part.expected_cost()))
        .sum();
    MESH_ENTRY_COST + whole.expected_cost() < apart
}

/// One primitive for the meshes of `group` (all of `kind`), or `None` where
/// the merged mesh cannot be built (more vertices than 32-bit indices
/// reach).
fn merged_mesh(kind: MeshKind, group: &[(Primitive, TriangleMesh)]) -> Option<Primitive> {
    fn append<T: Clone>(to: &mut Option<Vec<T>>, from: &Option<Vec<T>>) {
        if let (Some(to), Some(from)) = (to.as_mut(), from) {
            to.extend_from_slice(from);
        }
    }
    fn start<T>(present: bool) -> Option<Vec<T>> {
        present.then(Vec::new)
    }
    let mut mesh = TriangleMesh {
        normals: start(kind.normals),
        uvs: start(kind.uvs),
        uvs1: start(kind.uvs1),
        colors: start(kind.colors),
        tangents: start(kind.tangents),
        face_indices: start(kind.face_indices),
        ..TriangleMesh::default()
    };
    let mut faces = FaceTables::default();
    for (prim, data) in group {
        let base = u32::try_from(mesh.positions.len()).ok()?;
        base.checked_add(u32::try_from(data.positions.len()).ok()?)?;
        mesh.positions.extend_from_slice(&data.positions);
        mesh.indices.extend(data.indices.iter().map(|t| t.map(|i| i + base)));
        append(&mut mesh.normals, &data.normals);
        append(&mut mesh.uvs, &data.uvs);
        append(&mut mesh.uvs1, &data.uvs1);
        append(&mut mesh.colors, &data.colors);
        append(&mut mesh.tangents, &data.tangents);
        append(&mut mesh.face_indices, &data.face_indices);
        for face in 0..data.indices.len() as u32 {
            faces.push(prim.face_material(face), prim.face_area_light(face));
        }
    }
    mesh.material_ids = Some(std::mem::take(&mut faces.material_ids));
    let mesh = Mesh::new(mesh).ok()?.with_default_uv(kind.default_uv);
    Some(faces.primitive(mesh))
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

    /// A mesh primitive of axis-aligned boxes `[lo, hi]` (twelve triangles
    /// each; a flat box is one quad), with `uv`s on every vertex
    /// so that the hit records carry them.
    fn boxes(parts: &[(Vec3, Vec3)], material: MaterialId) -> Primitive {
        let mut mesh = TriangleMesh { uvs: Some(Vec::new()), ..TriangleMesh::default() };
        for &(lo, hi) in parts {
            let base = mesh.positions.len() as u32;
            for k in 0..8 {
                let pick = |bit: usize, axis: usize| if k & bit == 0 { lo[axis] } else { hi[axis] };
                mesh.positions.push(Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)));
                mesh.uvs.as_mut().unwrap().push(crate::geometry::Vec2::new((k & 3) as f32 / 3.0, (k >> 2) as f32));
            }
            // Two triangles for each face of the cube, by corner bits and
            // the axis the face is across; a flat box is one quad, its
            // other faces (coincident or without area) left out.
            let faces = [
                (2, [0, 1, 3, 2]),
                (2, [4, 6, 7, 5]),
                (1, [0, 4, 5, 1]),
                (1, [2, 3, 7, 6]),
                (0, [0, 2, 6, 4]),
                (0, [1, 5, 7, 3]),
            ];
            let flat = (0..3).find(|&axis| lo[axis] == hi[axis]);
            for (i, (axis, [a, b, c, d])) in faces.into_iter().enumerate() {
                if flat.is_some_and(|f| f != axis || i % 2 == 1) {
                    continue;
                }
                mesh.indices.push([base + a, base + b, base + c]);
                mesh.indices.push([base + a, base + c, base + d]);
            }
        }
        Primitive::new(Arc::new(Mesh::new(mesh).unwrap()), Transform::IDENTITY, material)
    }

    fn mesh_count(prims: &[Primitive]) -> usize {
        prims.iter().filter(|p| matches!(p.shape(), Shape::Mesh(_))).count()
    }

    /// A room like a Cornell box, open at the front: five walls of one face each (flat boxes),
    /// two blocks standing just above the floor, and an emitting panel under the ceiling, each a
    /// mesh of its own with its own material.
    fn room() -> Vec<Primitive> {
        let v = Vec3::new;
        let m = MaterialId::new;
        vec![
            boxes(&[(v(0.0, 0.0, 0.0), v(1.0, 0.0, 1.0))], m(0)),
            boxes(&[(v(0.0, 1.0, 0.0), v(1.0, 1.0, 1.0))], m(0)),
            boxes(&[(v(0.0, 0.0, 1.0), v(1.0, 1.0, 1.0))], m(0)),
            boxes(&[(v(0.0, 0.0, 0.0), v(0.0, 1.0, 1.0))], m(1)),
            boxes(&[(v(1.0, 0.0, 0.0), v(1.0, 1.0, 1.0))], m(2)),
            boxes(&[(v(0.15, 0.02, 0.2), v(0.45, 0.3, 0.5))], m(3)),
            boxes(&[(v(0.55, 0.02, 0.5), v(0.85, 0.6, 0.8))], m(3)),
            boxes(&[(v(0.4, 0.99, 0.4), v(0.6, 0.99, 0.6))], m(4)).with_area_light(0),
        ]
    }

    /// The meshes of a room enter each other's boxes, so the heuristic
    /// merges them; the merged mesh must give every ray the hit record its
    /// own mesh gave: the same distance, material, area light, normals and
    /// texture coordinates, bit for bit.
    #[test]
    fn a_rooms_meshes_merge_and_hit_as_before() {
        let primitives = room();
        let merged = merge_small_meshes(primitives.clone());
        assert_eq!(mesh_count(&merged), 1, "the room's eight meshes become one");
        let (bvh, list) = (BvhAggregate::new(&merged), LinearAggregate::new(primitives));
        let mut rng = Pcg32::new(4, 9);
        let (mut hits, mut lit) = (0, 0);
        for _ in 0..20_000 {
            let o = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.98 + Vec3::splat(0.01);
            let d = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
            let ray = Ray::new(o, d);
            assert_eq!(bvh.intersect_p(&ray, 0.3), list.intersect_p(&ray, 0.3), "ray {ray:?}");
            let (a, b) = (bvh.intersect(&ray, f32::INFINITY), list.intersect(&ray, f32::INFINITY));
            let (Some(a), Some(b)) = (a, b) else {
                assert_eq!(a.is_some(), b.is_some(), "ray {ray:?}");
                continue;
            };
            hits += 1;
            lit += a.light.is_some() as u32;
            assert_eq!((a.t, a.material, a.light), (b.t, b.material, b.light), "ray {ray:?}");
            assert_eq!((a.p, a.n, a.ns, a.uv), (b.p, b.n, b.ns, b.uv), "ray {ray:?}");
        }
        assert!(hits > 15_000 && lit > 50, "{hits} hits, {lit} on the light");
    }

    /// Small plates far apart above a large floor (the Veach MIS scene's
    /// layout): a ray that enters the merged mesh's box would rarely have
    /// entered a plate's, so the heuristic keeps the meshes apart.
    #[test]
    fn meshes_far_apart_stay_apart() {
        let v = Vec3::new;
        let m = MaterialId::new(0);
        let mut primitives = vec![
            boxes(&[(v(-10.0, 0.0, -10.0), v(10.0, 0.0, 10.0))], m),
            boxes(&[(v(-10.0, 0.0, -10.0), v(10.0, 10.0, -10.0))], m),
        ];
        for i in 0..4 {
            let x = -6.0 + 4.0 * i as f32;
            primitives.push(boxes(&[(v(x, 2.0 + i as f32, 0.0), v(x + 0.5, 2.05 + i as f32, 0.1))], m));
        }
        assert_eq!(mesh_count(&merge_small_meshes(primitives)), 6);
    }

    /// What the heuristic weighs, on the room: the merged mesh's expected
    /// cost against the parts', each part weighted by its box's share of the
    /// room's surface area.
    #[test]
    fn the_room_is_cheaper_merged_by_the_surface_area_heuristic() {
        let mesh_of = |p: &Primitive| match p.shape() {
            Shape::Mesh(mesh) => Arc::clone(mesh),
            _ => unreachable!("the room is meshes"),
        };
        let group: Vec<(Primitive, TriangleMesh)> =
            room().into_iter().map(|p| (p.clone(), mesh_of(&p).to_triangle_mesh())).collect();
        let kind = MeshKind::of(&mesh_of(&group[0].0), &group[0].1);
        let merged = merged_mesh(kind, &group).expect("the room merges");
        // Six faces of the unit cube.
        assert_eq!(mesh_of(&merged).bounds().surface_area(), 6.0);
        // Each wall is a unit square whose flat box has area 2, a third of
        // the room's; its tree is one leaf of two triangles under the root,
        // so a query in it costs the root's box test and one block.
        for (wall, _) in &group[..5] {
            assert_eq!(mesh_of(wall).bounds().surface_area(), 2.0);
            assert_eq!(mesh_of(wall).expected_cost(), 2.0);
        }
        // Apart, the five walls alone cost 5/3 × (entry + 2) = 5 of the
        // 6.0 the eight meshes cost; merged, the room costs 5.48.
        let apart: f32 = group
            .iter()
            .map(|(p, _)| mesh_of(p).bounds().surface_area() / 6.0 * (MESH_ENTRY_COST + mesh_of(p).expected_cost()))
            .sum();
        let whole = MESH_ENTRY_COST + mesh_of(&merged).expected_cost();
        assert!(whole < apart, "merged {whole}, apart {apart}");
        assert!(merging_pays(&merged, &group));
    }
}
