//! Primitives: shapes placed in the world with a material, and the
//! aggregates that find which of many primitives a ray hits first (pbrt-v4's
//! `Primitive`, `GeometricPrimitive` and `BVHAggregate`, §7.1).

mod aggregate;
mod merge;

pub use aggregate::{Aggregate, BvhAggregate, LinearAggregate};
pub(crate) use merge::{merge_loose_triangles, merge_small_meshes};

use crate::geometry::{Bounds3, Ray, Transform, Vec3};
use crate::interaction::SurfaceInteraction;
use crate::material::MaterialId;
use crate::medium::MediumInterface;
use crate::shapes::{Shape, ShapeHit};
use crate::texture::{FloatTexture, TextureContext};
use std::sync::Arc;

/// A shape placed in the world: the shape in its object space, the
/// transform from object to world space, and its material.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    shape: Shape,
    /// Object-to-world transform; `None` for the identity, which saves two
    /// matrix products per test.
    transform: Option<Transform>,
    material: MaterialId,
    /// For meshes with their own materials: scene material of each
    /// mesh-local material index.
    face_materials: Option<Arc<[MaterialId]>>,
    /// For emissive primitives: the index of the area light of face 0 in
    /// the scene's area lights (face `i` is `first + i`).
    area_light: Option<u32>,
    /// For merged meshes: the area light of each face, or [`NO_LIGHT`].
    face_lights: Option<Arc<[u32]>>,
    /// Alpha cut-out: where it is 0 the surface does not exist.
    alpha: Option<Arc<FloatTexture>>,
    /// Whether every hit's normals are negated (pbrt-v4's
    /// `ReverseOrientation`).
    reverse_orientation: bool,
    /// The media on the two sides of the surface.
    media: MediumInterface,
}

/// In a per-face light table: the face does not emit.
pub(crate) const NO_LIGHT: u32 = u32::MAX;

impl Primitive {
    /// Place `shape` in the world with `transform` (object to world).
    pub fn new(shape: impl Into<Shape>, transform: Transform, material: MaterialId) -> Self {
        let transform = (!transform.is_identity()).then_some(transform);
        Self {
            shape: shape.into(),
            transform,
            material,
            face_materials: None,
            area_light: None,
            face_lights: None,
            alpha: None,
            reverse_orientation: false,
            media: MediumInterface::NONE,
        }
    }

    /// Give a mesh's faces the materials its file assigns them:
    /// `table[i]` is the scene material of the mesh's material `i`. Faces
    /// without an assignment keep the primitive's material.
    pub fn with_face_materials(mut self, table: Arc<[MaterialId]>) -> Self {
        self.face_materials = Some(table);
        self
    }

    /// Give the surface an alpha cut-out (pbrt-v4's `alpha` parameter,
    /// `GeometricPrimitive::Intersect`): where `alpha` is 0 the surface does
    /// not exist for any ray (camera, bounce or shadow), where it is 1 it
    /// is opaque, and in between a hit exists with probability `alpha`,
    /// decided by a hash of the ray's origin and direction (so the same ray
    /// always gets the same answer). The texture is evaluated at each
    /// candidate hit with a [`TextureContext`] of its world-space point,
    /// geometric normal and uv; for a mesh inside its BVH traversal, so a
    /// cut-out triangle shows the nearest one behind it. A constant alpha
    /// of 1 or more is no cut-out at all and is dropped.
    pub fn with_alpha(mut self, alpha: FloatTexture) -> Self {
        self.alpha = match alpha {
            FloatTexture::Constant(a) if a >= 1.0 => None,
            a => Some(Arc::new(a)),
        };
        self
    }

    /// Turn the surface inside out when `reverse`: every hit reports the
    /// negated geometric and shading normals, so the side a dielectric
    /// calls its outside (and a BSDF its upper hemisphere) is the other one.
    /// This is pbrt-v4's `ReverseOrientation`: a quadric's normal negated
    /// at the hit (`flipNormal`, PBRT 4th ed., §6.2.2), and a triangle
    /// mesh's vertex normals negated with the geometric normal following
    /// them (or, without vertex normals, the geometric normal negated),
    /// which is the same as negating both at the hit. The side an area
    /// light emits from is the light's own affair (the scene builder's
    /// `Emission::reverse`).
    pub fn with_reverse_orientation(mut self, reverse: bool) -> Self {
        self.reverse_orientation = reverse;
        self
    }

    /// Make the surface the boundary between two media (see
    /// [`crate::medium`]): `inside` on the side opposite its geometric
    /// normal, `outside` on the normal's side (after
    /// [`Primitive::with_reverse_orientation`]).
    pub fn with_media(mut self, media: MediumInterface) -> Self {
        self.media = media;
        self
    }

    /// The media on the surface's two sides.
    pub fn media(&self) -> MediumInterface {
        self.media
    }

    /// Whether the surface's normals are negated
    /// ([`Primitive::with_reverse_orientation`]).
    pub fn reverse_orientation(&self) -> bool {
        self.reverse_orientation
    }

    /// The alpha cut-out texture, if any.
    pub fn alpha(&self) -> Option<&FloatTexture> {
        self.alpha.as_deref()
    }

    /// Mark the primitive as emissive: face `i` belongs to area light
    /// `first + i` (see the scene builder's `add_emissive`).
    pub(crate) fn with_area_light(mut self, first: u32) -> Self {
        self.area_light = Some(first);
        self
    }

    /// Give each face its own area light: `table[face]` is the index of its
    /// area light in the scene, or [`NO_LIGHT`] (used for the meshes that
    /// loose triangles are merged into, whose faces come from different
    /// primitives).
    pub(crate) fn with_face_lights(mut self, table: Arc<[u32]>) -> Self {
        self.face_lights = Some(table);
        self
    }

    /// Renumber the area lights of the primitive's faces: face light `l`
    /// becomes `remap[l]` (after the builder merged lights). Where the
    /// faces' new lights are no longer consecutive, the primitive gets a
    /// per-face table.
    pub(crate) fn remap_area_lights(&mut self, remap: &[u32]) {
        let new = |l: u32| if l == NO_LIGHT { l } else { remap[l as usize] };
        if let Some(table) = &self.face_lights {
            self.face_lights = Some(table.iter().map(|&l| new(l)).collect());
        }
        if let Some(first) = self.area_light {
            let faces = match &self.shape {
                Shape::Mesh(mesh) => mesh.triangle_count() as u32,
                _ => 1,
            };
            let consecutive = (0..faces).all(|f| new(first + f) == new(first) + f);
            if !consecutive && self.face_lights.is_none() {
                self.face_lights = Some((0..faces).map(|f| new(first + f)).collect());
            }
            self.area_light = Some(new(first));
        }
    }

    /// The same primitive placed with another transform (object to world);
    /// not emissive (the builder makes a placed copy emit).
    pub fn with_transform(&self, transform: Transform) -> Self {
        let transform = (!transform.is_identity()).then_some(transform);
        Self { transform, area_light: None, face_lights: None, ..self.clone() }
    }

    /// The scene material of each of a mesh's own material indices, if the
    /// mesh's faces have their own materials.
    pub fn face_materials(&self) -> Option<&[MaterialId]> {
        self.face_materials.as_deref()
    }

    /// The area light of face `face` (0 for shapes other than meshes), if
    /// it emits.
    pub fn face_area_light(&self, face: u32) -> Option<u32> {
        match &self.face_lights {
            Some(table) => table.get(face as usize).copied().filter(|&l| l != NO_LIGHT),
            None => self.area_light.map(|first| first + face),
        }
    }

    /// The material of face `face` (0 for shapes other than meshes): the
    /// face's own through [`Primitive::face_materials`], else the
    /// primitive's.
    pub fn face_material(&self, face: u32) -> MaterialId {
        self.material_at(face)
    }

    /// The index of the first of the primitive's area lights, if it emits.
    pub fn area_light(&self) -> Option<u32> {
        self.area_light
    }

    #[inline]
    fn material_at(&self, face: u32) -> MaterialId {
        if let (Some(table), Shape::Mesh(mesh)) = (&self.face_materials, &self.shape) {
            if let Some(&m) = mesh.material_of(face).and_then(|i| table.get(i as usize)) {
                return m;
            }
        }
        self.material
    }

    /// The shape, in object space.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The object-to-world transform.
    pub fn transform(&self) -> Transform {
        self.transform.unwrap_or_default()
    }

    /// The material.
    pub fn material(&self) -> MaterialId {
        self.material
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        match &self.transform {
            None => self.shape.bounds(),
            Some(t) => t.bounds(&self.shape.bounds()),
        }
    }

    /// The nearest hit with `0 < t < t_max`. The ray is intersected in
    /// object space through the inverse transform; the point returns through
    /// the transform (with its error bound) and the normals through the
    /// inverse transpose.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        let mut hit = None;
        self.intersect_closer(ray, t_max, &mut hit);
        hit
    }

    /// [`Primitive::intersect`] for a caller that keeps the closest hit so
    /// far in `closest`: a hit with `0 < t < t_max` is written there (and
    /// `true` returned); without one, `closest` is left as it was. An
    /// untransformed mesh without alpha, the common case, builds its hit
    /// record in `closest` itself, so that it is not copied on its way up
    /// (see [`Aggregate::intersect_into`]).
    #[inline]
    pub fn intersect_closer(&self, ray: &Ray, t_max: f32, closest: &mut Option<SurfaceInteraction>) -> bool {
        if let (None, None, Shape::Mesh(mesh)) = (&self.transform, &self.alpha, &self.shape) {
            let Some(hit) = mesh.intersect_triangle(ray, t_max) else { return false };
            *closest = Some(self.interaction(mesh.hit_record(&hit), None));
            return true;
        }
        self.intersect_closer_any(ray, t_max, closest)
    }

    /// [`Primitive::intersect_closer`] for any transform, alpha and shape.
    fn intersect_closer_any(&self, ray: &Ray, t_max: f32, closest: &mut Option<SurfaceInteraction>) -> bool {
        let (hit, t) = match (&self.transform, &self.alpha) {
            (None, None) => (self.shape.intersect(ray, t_max), None),
            (Some(t), None) => (self.shape.intersect(&t.ray_to_object(ray), t_max), Some(t)),
            (t, Some(alpha)) => {
                let object_ray = t.map(|t| t.ray_to_object(ray));
                let u = ray_hash(ray);
                let mut accept = |h: &ShapeHit| self.alpha_accepts(alpha, t.as_ref(), h, u);
                (self.shape.intersect_filtered(object_ray.as_ref().unwrap_or(ray), t_max, &mut accept), t.as_ref())
            }
        };
        let Some(hit) = hit else { return false };
        *closest = Some(self.interaction(hit, t));
        true
    }

    /// The surface interaction of the shape's hit `hit` (in object space
    /// under the transform `t`).
    #[inline(always)]
    fn interaction(&self, hit: ShapeHit, t: Option<&Transform>) -> SurfaceInteraction {
        let (p, p_error, mut n, mut ns, dpdu, dpdv) = match t {
            None => (hit.p, hit.p_error, hit.n, hit.ns, hit.dpdu, hit.dpdv),
            Some(t) => {
                let (p, err) = t.point_with_error(hit.p, hit.p_error);
                let n = t.normal(hit.n).normalize();
                let ns = if hit.ns == hit.n { n } else { t.normal(hit.ns).normalize() };
                (p, err, n, ns, t.vector(hit.dpdu), t.vector(hit.dpdv))
            }
        };
        if self.reverse_orientation {
            (n, ns) = (-n, -ns);
        }
        SurfaceInteraction {
            t: hit.t,
            p,
            p_error,
            n,
            ns,
            uv: hit.uv,
            attributes: hit.attributes,
            dpdu,
            dpdv,
            material: self.material_at(hit.face),
            light: match &self.face_lights {
                None => self.area_light.map(|first| first + hit.face),
                Some(table) => table.get(hit.face as usize).copied().filter(|&l| l != NO_LIGHT),
            },
            media: self.media,
        }
    }

    /// Whether any hit with `0 < t < t_max` exists.
    #[inline]
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        match (&self.transform, &self.alpha) {
            (None, None) => match &self.shape {
                Shape::Mesh(mesh) => mesh.intersect_p(ray, t_max),
                shape => shape.intersect_p(ray, t_max),
            },
            (Some(t), None) => self.shape.intersect_p(&t.ray_to_object(ray), t_max),
            (t, Some(alpha)) => {
                let object_ray = t.map(|t| t.ray_to_object(ray));
                let u = ray_hash(ray);
                let mut accept = |h: &ShapeHit| self.alpha_accepts(alpha, t.as_ref(), h, u);
                self.shape.intersect_p_filtered(object_ray.as_ref().unwrap_or(ray), t_max, &mut accept)
            }
        }
    }

    /// Whether the candidate hit `h` (object space) survives the alpha
    /// test: `alpha ≥ 1` keeps it, `alpha ≤ 0` drops it, and in between it
    /// is kept when the ray's hash `u ∈ [0, 1)` is below alpha (pbrt-v4).
    #[inline]
    fn alpha_accepts(&self, alpha: &FloatTexture, t: Option<&Transform>, h: &ShapeHit, u: f32) -> bool {
        let (p, n) = match t {
            None => (h.p, h.n),
            Some(t) => (t.point(h.p), t.normal(h.n).normalize_or_zero()),
        };
        let a = alpha.evaluate(&TextureContext::new(p, n, h.uv).with_attributes(h.attributes));
        if a >= 1.0 {
            true
        } else if a <= 0.0 || a.is_nan() {
            false
        } else {
            u < a
        }
    }
}

/// A number in `[0, 1)` hashed from a ray's origin and direction, for
/// stochastic alpha (pbrt-v4 hashes them the same way, `HashFloat(r.o,
/// r.d)`): the bits of the six coordinates are mixed with the 64-bit
/// finaliser of MurmurHash3 (Appleby) and the top 24 bits are kept.
#[inline]
fn ray_hash(ray: &Ray) -> f32 {
    let mix = |mut h: u64| {
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    };
    let bits = |v: Vec3| (u64::from(v.x.to_bits()) << 32 | u64::from(v.y.to_bits()), u64::from(v.z.to_bits()));
    let (o0, o1) = bits(ray.origin);
    let (d0, d1) = bits(ray.dir);
    let mut h = mix(o0 ^ 0x9e37_79b9_7f4a_7c15);
    for w in [o1, d0, d1] {
        h = mix(h ^ w.wrapping_add(0x9e37_79b9_7f4a_7c15));
    }
    (h >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use crate::mesh::TriangleMesh;
    use crate::shapes::Mesh;

    /// The unit square in z = 0 as two triangles, uv = (x, y).
    fn square(z: f32) -> Arc<Mesh> {
        let positions =
            vec![Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(1.0, 1.0, z), Vec3::new(0.0, 1.0, z)];
        let uvs = Some(positions.iter().map(|p| p.truncate()).collect());
        Arc::new(
            Mesh::new(TriangleMesh { positions, indices: vec![[0, 1, 2], [0, 2, 3]], uvs, ..Default::default() })
                .unwrap(),
        )
    }

    fn down(x: f32, y: f32) -> Ray {
        Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z)
    }

    #[test]
    fn alpha_zero_is_invisible_to_every_ray() {
        let m = MaterialId::new(0);
        let opaque = Primitive::new(Shape::Mesh(square(0.0)), Transform::IDENTITY, m);
        let cut = opaque.clone().with_alpha(FloatTexture::Constant(0.0));
        assert!(opaque.intersect(&down(0.3, 0.6), f32::INFINITY).is_some());
        assert!(cut.intersect(&down(0.3, 0.6), f32::INFINITY).is_none());
        assert!(!cut.intersect_p(&down(0.3, 0.6), f32::INFINITY));
        // Placed with a transform, and for a sphere: the same.
        let moved = cut.with_transform(Transform::translate(Vec3::new(0.0, 0.0, 1.0)));
        assert!(moved.intersect(&down(0.3, 0.6), f32::INFINITY).is_none());
        let ball = Primitive::new(crate::shapes::Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::IDENTITY, m)
            .with_alpha(FloatTexture::Constant(0.0));
        assert!(ball.intersect(&down(0.0, 0.0), f32::INFINITY).is_none());
        assert!(!ball.intersect_p(&down(0.0, 0.0), f32::INFINITY));
        // Alpha 1 is no cut-out at all.
        assert!(opaque.clone().with_alpha(FloatTexture::Constant(1.0)).alpha().is_none());
    }

    #[test]
    fn stochastic_alpha_keeps_its_fraction_and_is_deterministic() {
        let m = MaterialId::new(0);
        let p =
            Primitive::new(Shape::Mesh(square(0.0)), Transform::IDENTITY, m).with_alpha(FloatTexture::Constant(0.25));
        let n = 20_000;
        let mut hits = 0;
        for i in 0..n {
            let r = down((i % 100) as f32 / 100.0 + 0.003, (i / 100) as f32 / 200.0 + 0.001);
            let h = p.intersect(&r, f32::INFINITY).is_some();
            assert_eq!(h, p.intersect_p(&r, f32::INFINITY), "camera and shadow rays agree");
            hits += h as u32;
        }
        let frac = hits as f32 / n as f32;
        assert!((frac - 0.25).abs() < 0.02, "{frac}");
    }

    #[test]
    fn a_cut_out_nearest_triangle_shows_the_one_behind() {
        // Two squares in one mesh, at z = 1 and z = 0; a filter that drops
        // faces 0 and 1 (the upper square) reveals the lower one.
        let mut mesh = TriangleMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(1.0, 1.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
            ],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Default::default()
        };
        mesh.positions.extend(mesh.positions.clone().iter().map(|p| Vec3::new(p.x, p.y, 0.0)));
        mesh.indices.extend([[4, 5, 6], [4, 6, 7]]);
        let mesh = Mesh::new(mesh).unwrap();
        let h = mesh.intersect_filtered(&down(0.7, 0.2), f32::INFINITY, &mut |h| h.face >= 2).unwrap();
        assert_eq!((h.t, h.face), (5.0, 2));
        assert!(mesh.intersect_p_filtered(&down(0.7, 0.2), f32::INFINITY, &mut |h| h.face >= 2));
        assert!(!mesh.intersect_p_filtered(&down(0.7, 0.2), f32::INFINITY, &mut |_| false));
        // Without the filter: the upper one.
        assert_eq!(mesh.intersect(&down(0.7, 0.2), f32::INFINITY).unwrap().t, 4.0);
    }

    #[test]
    fn a_checker_alpha_cuts_exact_squares() {
        // alpha = 1 on the even squares of a 4 × 4 checker in uv, 0 on the
        // odd ones (the test the alpha texture makes, here as a closure on
        // the hit's uv: the float checker texture lives in `texture`).
        let mesh = square(0.0);
        let checker = |uv: Vec2| ((uv.x * 4.0).floor() as i32 + (uv.y * 4.0).floor() as i32) % 2 == 0;
        for j in 0..64 {
            for i in 0..64 {
                let (x, y) = ((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let hit = mesh.intersect_filtered(&down(x, y), f32::INFINITY, &mut |h| checker(h.uv));
                assert_eq!(hit.is_some(), checker(Vec2::new(x, y)), "({x}, {y})");
                if let Some(h) = hit {
                    assert!((h.uv - Vec2::new(x, y)).length() < 1e-6);
                }
            }
        }
    }
}
