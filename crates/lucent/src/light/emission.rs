//! Emission sampling: rays of light leaving a light, for the integrators
//! that trace paths from the lights (bidirectional path tracing, light
//! tracing).
//!
//! [`Emitter::sample_le`] draws a ray leaving a light, with the density of
//! its origin (per unit area, or 1 for a delta position) and of its
//! direction (per unit solid angle, or 1 for a delta direction);
//! [`Emitter::pdf_le`] gives both densities of a given ray. Following
//! pbrt-v4's `SampleLe` and `PDF_Le` of each light (the light-ray sampling
//! of PBRT 3rd ed., §16.1.2, in pbrt-v4's form; the lights themselves are
//! PBRT 4th ed., §12.2–§12.5):
//!
//! * a point light: its position, a direction uniform on the sphere;
//! * a spot light: its position, a direction uniform in its cone;
//! * an area light: a point uniform by area, a cosine-weighted direction
//!   about the emitting side's normal (one of the two sides, chosen with
//!   probability ½, when two-sided);
//! * lights at infinity (directional, environment): a direction (the
//!   light's own, or sampled as [`Environment::sample_li`] samples it), and
//!   an origin on a disk of the scene's bounding sphere's radius `r`,
//!   perpendicular to it, just outside that sphere, so that the rays cover
//!   everything the light can reach in the scene with density `1/(π r²)`.
//!
//! With a light's sample `(ray, L, p_pos, p_dir)`, the flux it emits is
//! `Φ = E[L |cos θ| / (p_pos p_dir)]` (`cos θ` between the ray and the
//! surface normal at an area light's origin, 1 otherwise), the
//! [`Emitter::power`] of the light.

use super::emitter::{scene_radius, LightSampleContext};
use super::{smooth_step, AreaLight, Emitter, Environment, Light};
use crate::color::Color;
use crate::geometry::{gamma, offset_ray_origin, Bounds3, Frame, Ray, Vec2, Vec3};
use crate::interaction::SurfaceInteraction;
use crate::sampling::{concentric_disk, cosine_hemisphere, cosine_hemisphere_pdf, uniform_sphere};
use crate::shapes::Shape;
use std::f32::consts::{FRAC_1_PI, PI};

/// A ray of light leaving a light (pbrt-v4 `LightLeSample`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeSample {
    /// The ray: origin on the light (or, for lights at infinity, on a disk
    /// outside the scene's bounding sphere), unit direction of travel.
    ///
    /// An area light's origin is the sampled point of its surface pushed off
    /// it, along [`LeSample::n`], by a bound on the point's rounding error
    /// (as pbrt-v4's `SpawnRay`, PBRT 4th ed., §6.8.6): the ray can be
    /// traced as it is, without meeting the surface it leaves.
    pub ray: Ray,
    /// Unit surface normal at the origin, on the emitting side the ray
    /// leaves from (`n · ray.dir > 0`; area lights); zero for point, spot
    /// and lights at infinity.
    pub n: Vec3,
    /// Emitted radiance along the ray (point and spot lights: the intensity
    /// `I` towards the direction, with the spot's cone falloff and no
    /// distance falloff; directional: its intensity, the irradiance on a
    /// surface facing it; environment: [`Environment::le`]`(−ray.dir)`, the
    /// radiance it sends into the scene from direction `−ray.dir`, where the
    /// ray comes from).
    pub l: Color,
    /// Density of the origin: per unit area for area lights (`1/A`) and for
    /// the disk of lights at infinity (`1/(π r²)`); 1 for point and spot
    /// lights (a delta position).
    pub pdf_pos: f32,
    /// Density of the direction per unit solid angle (1 for the directional
    /// light's delta direction).
    pub pdf_dir: f32,
}

/// Uniform density over the sphere of directions, `1/(4π)`.
const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

impl Emitter {
    /// Sample a ray leaving the light, from uniform `u_pos`, `u_dir` in
    /// `[0, 1)²`: `u_pos` picks the origin (unused by point and spot
    /// lights), `u_dir` the direction (unused by directional lights).
    /// `scene` bounds the scene: lights at infinity place the disk of their
    /// origins on its bounding sphere (centre the box's centre, radius half
    /// its diagonal as [`Emitter::power`]; an empty or unbounded box counts
    /// as the unit sphere at the origin). `None` when the light emits
    /// nothing along the sampled ray (black, outside a spot's cone, an area
    /// light of a shape that is not sampled, a zero-radius scene for lights
    /// at infinity...).
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, scene: &Bounds3) -> Option<LeSample> {
        let s = match self {
            Emitter::Delta(light) => light.sample_le(u_pos, u_dir, scene),
            Emitter::Area(area) => area.sample_le(u_pos, u_dir),
            Emitter::Environment(env) => env.sample_le(u_pos, u_dir, scene),
        }?;
        let usable = s.l != Color::ZERO
            && s.l.is_finite()
            && s.pdf_pos > 0.0
            && s.pdf_pos.is_finite()
            && s.pdf_dir > 0.0
            && s.pdf_dir.is_finite();
        usable.then_some(s)
    }

    /// `(pdf_pos, pdf_dir)` with which [`Emitter::sample_le`] would produce
    /// a ray leaving the light at `origin`, where the unit geometric normal
    /// is `n` (area lights; either orientation, ignored by other lights), in
    /// unit direction `dir` of travel. `scene` is as for `sample_le`.
    ///
    /// * Point light: `(1, 1/(4π))`.
    /// * Spot light: `(1, 1/(2π (1 − cos θ_total)))`, whatever `dir` (as
    ///   pbrt-v4's `SpotLight::PDF_Le`: outside the cone the light emits
    ///   nothing, so no path that carries light leaves it there).
    /// * Directional light: `(1/(π r²), 1)`, whatever `dir` (a delta
    ///   direction: the value of its sampling).
    /// * Area light: `(1/A, cos θ/π)`, `cos θ` between `dir` and the emitting
    ///   side's normal, 0 for `dir` on the other side; two-sided
    ///   `(1/A, |cos θ|/(2π))`. `(0, 0)` for a shape that is not sampled (a
    ///   plane, a mesh).
    /// * Environment: `(1/(π r²), pdf_li(−dir))` ([`Environment::pdf_li`]).
    ///
    /// The origin is not checked to lie on the light (on its disk, for
    /// lights at infinity). With a zero-radius scene the position density
    /// of lights at infinity is 0.
    pub fn pdf_le(&self, origin: Vec3, n: Vec3, dir: Vec3, scene: &Bounds3) -> (f32, f32) {
        match self {
            Emitter::Delta(Light::Point { .. }) => (1.0, UNIFORM_SPHERE_PDF),
            Emitter::Delta(Light::Spot { cos_total, .. }) => (1.0, uniform_cone_pdf(*cos_total)),
            Emitter::Delta(Light::Directional { .. }) => (disk_pdf(scene_sphere(scene).1), 1.0),
            Emitter::Area(area) => area.pdf_le(origin, n, dir),
            Emitter::Environment(env) => (disk_pdf(scene_sphere(scene).1), env.pdf_li(-dir)),
        }
    }
}

impl Light {
    /// [`Emitter::sample_le`] for point, spot and directional lights
    /// (pbrt-v4's `PointLight::SampleLe`, `SpotLight::SampleLe`,
    /// `DistantLight::SampleLe`).
    ///
    /// Point and spot lights emit their intensity `I` per unit solid angle
    /// whatever their [`super::Falloff`]: a light with
    /// [`super::Falloff::None`] (constant with distance, the classic ray
    /// tracer's) has no physical emission distribution and is sampled as if
    /// it had the inverse-square falloff.
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, scene: &Bounds3) -> Option<LeSample> {
        match *self {
            // PBRT 4th ed., §12.2: a point light sends I equally in every
            // direction; directions uniform on the sphere, p_dir = 1/(4π).
            Light::Point { position, intensity, .. } => Some(LeSample {
                ray: Ray::new(position, uniform_sphere(u_dir)),
                n: Vec3::ZERO,
                l: intensity,
                pdf_pos: 1.0,
                pdf_dir: UNIFORM_SPHERE_PDF,
            }),
            // PBRT 4th ed., §12.2.1: directions uniform in the cone of
            // half-angle θ_total, p_dir = 1/(2π (1 − cos θ_total)), and the
            // intensity I · smoothstep(cos θ, cos θ_total, cos θ_start) that
            // `Light::sample_li` delivers.
            Light::Spot { position, direction, intensity, cos_total, cos_falloff_start, .. } => {
                let local = uniform_cone(u_dir, cos_total);
                let cone = smooth_step(local.z, cos_total, cos_falloff_start);
                Some(LeSample {
                    ray: Ray::new(position, Frame::from_z(direction).from_local(local).normalize()),
                    n: Vec3::ZERO,
                    l: intensity * cone,
                    pdf_pos: 1.0,
                    pdf_dir: uniform_cone_pdf(cos_total),
                })
            }
            // PBRT 4th ed., §12.3: the light's rays that reach the scene
            // cross the disk of radius r through the centre of its bounding
            // sphere, perpendicular to them; the origin is a point of that
            // disk, uniform by area (p_pos = 1/(π r²)), moved back by r so
            // that the ray starts outside the sphere.
            Light::Directional { direction, intensity } => {
                let (centre, r) = scene_sphere(scene);
                let p = disk_point(centre, r, direction, u_pos);
                Some(LeSample {
                    ray: Ray::new(p - r * direction, direction),
                    n: Vec3::ZERO,
                    l: intensity,
                    pdf_pos: disk_pdf(r),
                    pdf_dir: 1.0,
                })
            }
        }
    }
}

impl AreaLight {
    /// [`Emitter::sample_le`] for an area light (pbrt-v4's
    /// `DiffuseAreaLight::SampleLe`, PBRT 4th ed., §12.4): the origin uniform
    /// by area ([`Shape::sample_area`], `p_pos = 1/A`); the direction
    /// cosine-weighted about the normal of the emitting side (the shape's
    /// front side, or its back when [`AreaLight::reverse`]),
    /// `p_dir = cos θ/π`. A two-sided light picks the front side when
    /// `u_dir.x < ½`, the back otherwise, and stretches `u_dir.x` back to
    /// `[0, 1)`: `p_dir = cos θ/(2π)`.
    ///
    /// The radiance is [`AreaLight::emitted_at`] at the point towards the
    /// direction. With an [`super::EmissionImage`] the texture is looked up
    /// at the point's texture coordinates, found by intersecting the
    /// emitting primitive with a short ray through the point along the
    /// normal (from the emitting side, then from the other); `None` if
    /// neither meets it there (the point is in an alpha cut-out of the
    /// primitive, where it does not exist, or the intersection misses it by
    /// rounding).
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> Option<LeSample> {
        let s = self.shape.sample_area(u_pos)?;
        let area = self.area();
        if !(area > 0.0 && area.is_finite() && s.pdf > 0.0 && s.pdf.is_finite()) {
            return None;
        }
        let n = self.emitting_normal(s.p, s.n)?;
        let (n, u, pdf_scale) = if self.two_sided {
            if u_dir.x < 0.5 {
                (n, Vec2::new((2.0 * u_dir.x).min(ONE_MINUS_EPSILON), u_dir.y), 0.5)
            } else {
                (-n, Vec2::new((2.0 * (u_dir.x - 0.5)).min(ONE_MINUS_EPSILON), u_dir.y), 0.5)
            }
        } else {
            (n, u_dir, 1.0)
        };
        let local = cosine_hemisphere(u);
        let pdf_dir = cosine_hemisphere_pdf(local.z) * pdf_scale;
        if pdf_dir <= 0.0 {
            return None;
        }
        let dir = Frame::from_z(n).from_local(local).normalize();
        let l = match &self.image {
            None => self.emitted(s.p, Vec2::ZERO, dir),
            Some(image) => {
                let hit = surface_at(&image.surface, s.p, n, area)?;
                self.emitted_at(s.p, hit.uv, hit.attributes, dir)
            }
        };
        // The sampled point is within γ(16) of the magnitude of the shape's
        // coordinates (γ(5)–γ(7) for the samplers of spheres and triangles,
        // a few more operations for placed shapes).
        let b = self.shape.bounds();
        let p_error = gamma(16) * b.min.abs().max(b.max.abs());
        let origin = offset_ray_origin(s.p, p_error, n, dir);
        Some(LeSample { ray: Ray::new(origin, dir), n, l, pdf_pos: s.pdf, pdf_dir })
    }

    /// [`Emitter::pdf_le`] for an area light (pbrt-v4's
    /// `DiffuseAreaLight::PDF_Le`).
    fn pdf_le(&self, origin: Vec3, n: Vec3, dir: Vec3) -> (f32, f32) {
        let area = self.area();
        if matches!(self.shape, Shape::Plane(_) | Shape::Mesh(_)) || !(area > 0.0 && area.is_finite()) {
            return (0.0, 0.0);
        }
        let Some(n) = self.emitting_normal(origin, n) else {
            return (0.0, 0.0);
        };
        let cos = n.dot(dir);
        let pdf_dir =
            if self.two_sided { 0.5 * cosine_hemisphere_pdf(cos.abs()) } else { cosine_hemisphere_pdf(cos.max(0.0)) };
        (1.0 / area, pdf_dir)
    }

    /// The unit normal `n` (either orientation) at the point `p` of the
    /// light turned to its emitting side: the front side
    /// ([`Shape::front_side`]), or the back when [`AreaLight::reverse`]
    /// (the front for two-sided lights). `None` where the front side is
    /// unknown (a mesh) or `n` lies in the surface.
    fn emitting_normal(&self, p: Vec3, n: Vec3) -> Option<Vec3> {
        let front = self.shape.front_side(p);
        let cos = n.dot(front);
        if cos == 0.0 || cos.is_nan() {
            return None;
        }
        let n = if cos < 0.0 { -n } else { n };
        Some(if self.reverse && !self.two_sided { -n } else { n })
    }
}

/// The largest `f32` below 1 (pbrt-v4's `OneMinusEpsilon`).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The intersection of `surface` at its point `p` (unit normal `n`, area
/// `area`): a ray from `p + δ n` along `−n` with `t_max = 2δ`, then from
/// `p − δ n` along `n`. `δ` is a thousandth of the size `√area` of the
/// surface, and at least 10⁻⁵ of `p`'s largest coordinate, well above the
/// rounding of `p`. Along the normal the ray meets the surface at `p`
/// (curved surfaces too) and nothing else of it nearby.
fn surface_at(surface: &crate::primitive::Primitive, p: Vec3, n: Vec3, area: f32) -> Option<SurfaceInteraction> {
    let delta = (1e-3 * area.sqrt()).max(1e-5 * p.abs().max_element());
    if !(delta > 0.0 && delta.is_finite()) {
        return None;
    }
    [n, -n].into_iter().find_map(|side| surface.intersect(&Ray::new(p + delta * side, -side), 2.0 * delta))
}

/// A direction uniform in the cone of half-angle `θ_max` about `+z`
/// (`cos θ_max = cos_max`): `cos θ = (1 − u₀) + u₀ cos θ_max`,
/// `φ = 2π u₁` (PBRT 4th ed., §A.5.4, `SampleUniformCone`).
fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos = (1.0 - u.x) + u.x * cos_max;
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
    Vec3::new(sin * cos_phi, sin * sin_phi, cos)
}

/// The density of [`uniform_cone`] per unit solid angle:
/// `1/(2π (1 − cos θ_max))` (PBRT 4th ed., §A.5.4, `UniformConePDF`); 0
/// for a cone too narrow to have a finite one.
fn uniform_cone_pdf(cos_max: f32) -> f32 {
    let pdf = 1.0 / (2.0 * PI * (1.0 - cos_max));
    if pdf.is_finite() && pdf > 0.0 {
        pdf
    } else {
        0.0
    }
}

/// Density `1/(π r²)` of a point uniform on a disk of radius `r`; 0 for
/// `r = 0`.
fn disk_pdf(r: f32) -> f32 {
    let pdf = 1.0 / (PI * r * r);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

/// A point uniform by area ([`concentric_disk`]) on the disk of radius `r`
/// centred at `centre` perpendicular to the unit vector `axis`.
fn disk_point(centre: Vec3, r: f32, axis: Vec3, u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let f = Frame::from_z(axis);
    centre + r * (d.x * f.x + d.y * f.y)
}

/// The scene's bounding sphere: the centre of `bounds` and half its
/// diagonal ([`scene_radius`]); the unit sphere at the origin for an empty
/// or unbounded box, or one whose diagonal overflows.
fn scene_sphere(bounds: &Bounds3) -> (Vec3, f32) {
    let usable = !(bounds.is_empty() || bounds.is_infinite()) && (0.5 * (bounds.max - bounds.min).length()).is_finite();
    let centre = if usable { 0.5 * bounds.min + 0.5 * bounds.max } else { Vec3::ZERO };
    (centre, scene_radius(bounds))
}

impl Environment {
    /// [`Emitter::sample_le`] for an environment (pbrt-v4's
    /// `UniformInfiniteLight::SampleLe`, `ImageInfiniteLight::SampleLe`,
    /// PBRT 4th ed., §12.5.1–§12.5.2): the direction `wi` towards the light
    /// and its solid-angle density from [`Environment::sample_li`] (uniform
    /// on the sphere, or by the image's luminance); the ray travels along
    /// `−wi` with the radiance `le(wi)` that `sample_li` returns, from a
    /// point uniform on the disk of radius `r` perpendicular to `wi` through
    /// the scene's centre, moved out by `r` towards the light
    /// (`p_pos = 1/(π r²)`).
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, scene: &Bounds3) -> Option<LeSample> {
        let (centre, r) = scene_sphere(scene);
        let s = self.sample_li(&LightSampleContext { p: centre, n: Vec3::ZERO }, u_dir)?;
        let p = disk_point(centre, r, s.wi, u_pos);
        Some(LeSample {
            ray: Ray::new(p + r * s.wi, -s.wi),
            n: Vec3::ZERO,
            l: s.l,
            pdf_pos: disk_pdf(r),
            pdf_dir: s.pdf,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::luminance;
    use crate::light::{EmissionImage, EnvironmentMap, Falloff};
    use crate::material::MaterialId;
    use crate::primitive::Primitive;
    use crate::sampling::Pcg32;
    use crate::shapes::{Sphere, Triangle};
    use crate::texture::{Texture, TextureContext};
    use std::sync::Arc;

    /// The scene of every test: centre (1, 2, 3), radius 3.
    fn scene() -> Bounds3 {
        Bounds3::from_points(Vec3::new(-1.0, 1.0, 1.0), Vec3::new(3.0, 3.0, 5.0))
    }

    fn sphere_light() -> AreaLight {
        AreaLight {
            shape: Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, -2.0), 0.75).unwrap()),
            radiance: Color::splat(1.5),
            two_sided: false,
            reverse: false,
            image: None,
        }
    }

    fn triangle() -> [Vec3; 3] {
        [Vec3::new(-1.0, 2.0, 0.5), Vec3::new(1.5, 2.2, 0.0), Vec3::new(0.2, 3.0, 1.5)]
    }

    fn triangle_light(two_sided: bool, reverse: bool) -> AreaLight {
        AreaLight {
            shape: Shape::Triangle(Triangle::new(triangle(), None).unwrap()),
            radiance: Color::splat(2.0),
            two_sided,
            reverse,
            image: None,
        }
    }

    /// A lat-long map, turned by 30°: a dim background with a bright
    /// coloured patch.
    fn image_environment() -> Environment {
        let (w, h) = (32u32, 16u32);
        let mut px = vec![Color::new(0.1, 0.2, 0.3); (w * h) as usize];
        for y in 3..6 {
            for x in 20..25 {
                px[(y * w + x) as usize] = Color::new(20.0, 10.0, 5.0);
            }
        }
        Environment::Image(Arc::new(EnvironmentMap::new(w, h, px, 1.0, 30.0).unwrap()))
    }

    /// Every kind of light, named.
    fn lights() -> Vec<(&'static str, Emitter)> {
        vec![
            ("point", Emitter::Delta(Light::point(Vec3::new(1.0, 2.0, 0.5), Color::ONE, 3.0, Falloff::None).unwrap())),
            (
                "spot",
                Emitter::Delta(
                    Light::spot(
                        Vec3::new(0.0, 4.0, 0.0),
                        Vec3::new(0.3, -1.0, 0.2),
                        Color::ONE,
                        5.0,
                        40.0,
                        15.0,
                        Falloff::InverseSquare,
                    )
                    .unwrap(),
                ),
            ),
            ("directional", Emitter::Delta(Light::directional(Vec3::new(1.0, -2.0, 0.5), Color::ONE, 2.5).unwrap())),
            ("sphere", Emitter::Area(sphere_light())),
            ("triangle two-sided", Emitter::Area(triangle_light(true, false))),
            ("triangle reversed", Emitter::Area(triangle_light(false, true))),
            ("triangle", Emitter::Area(triangle_light(false, false))),
            ("constant environment", Emitter::Environment(Environment::Constant(Color::splat(0.7)))),
            ("image environment", Emitter::Environment(image_environment())),
        ]
    }

    fn samples(rng: &mut Pcg32) -> (Vec2, Vec2) {
        (Vec2::new(rng.uniform(), rng.uniform()), Vec2::new(rng.uniform(), rng.uniform()))
    }

    #[test]
    fn pdf_le_returns_the_densities_of_each_sample() {
        let b = scene();
        let mut rng = Pcg32::new(11, 0);
        for (name, light) in lights() {
            let (mut n_ok, mut mismatches) = (0usize, 0usize);
            for _ in 0..20_000 {
                let (u_pos, u_dir) = samples(&mut rng);
                let Some(s) = light.sample_le(u_pos, u_dir, &b) else { continue };
                n_ok += 1;
                let (pos, dir) = light.pdf_le(s.ray.origin, s.n, s.ray.dir, &b);
                let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.abs();
                assert!(close(pos, s.pdf_pos), "{name}: pdf_pos {pos} vs sample {}", s.pdf_pos);
                if !close(dir, s.pdf_dir) {
                    mismatches += 1;
                }
                // Area lights: the normal's orientation does not matter.
                if s.n != Vec3::ZERO {
                    assert_eq!(light.pdf_le(s.ray.origin, -s.n, s.ray.dir, &b), (pos, dir), "{name}");
                }
            }
            assert!(n_ok > 10_000, "{name}: {n_ok} samples");
            // An image environment recomputes the pixel of the direction:
            // rounding may move a direction on a pixel's edge to the next.
            let allowed = if name == "image environment" { n_ok / 1000 } else { 0 };
            assert!(mismatches <= allowed, "{name}: {mismatches} pdf_dir mismatches in {n_ok}");
        }
    }

    #[test]
    fn mc_power_matches_emitter_power() {
        let b = scene();
        for (k, (name, light)) in lights().into_iter().enumerate() {
            let mut rng = Pcg32::new(100 + k as u64, 3);
            let m = 100_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..m {
                let (u_pos, u_dir) = samples(&mut rng);
                let x = light.sample_le(u_pos, u_dir, &b).map_or(0.0, |s| {
                    let cos = if s.n == Vec3::ZERO { 1.0 } else { s.n.dot(s.ray.dir).abs() };
                    (luminance(s.l) * cos / (s.pdf_pos * s.pdf_dir)) as f64
                });
                sum += x;
                sum2 += x * x;
            }
            let mean = sum / m as f64;
            let se = ((sum2 / m as f64 - mean * mean).max(0.0) / m as f64).sqrt();
            let want = light.power(&b) as f64;
            assert!(want > 0.0, "{name}");
            assert!((mean - want).abs() <= 5.0 * se + 1e-3 * want, "{name}: MC {mean} ± {se}, power {want}");
        }
    }

    #[test]
    fn power_matches_the_closed_forms() {
        // The closed forms the brief names, for white lights (luminance of
        // white is 1).
        assert!((luminance(Color::ONE) - 1.0).abs() < 1e-6);
        let b = scene();
        let r = 3.0f32;
        let want = [
            ("point", 4.0 * PI * 3.0),
            ("spot", 2.0 * PI * 5.0 * (1.0 - 0.5 * (40f32.to_radians().cos() + 25f32.to_radians().cos()))),
            ("directional", PI * r * r * 2.5),
            ("sphere", PI * 4.0 * PI * 0.75 * 0.75 * 1.5),
            ("constant environment", PI * r * r * 4.0 * PI * 0.7),
        ];
        for (name, light) in lights() {
            if let Some(&(_, w)) = want.iter().find(|(n, _)| *n == name) {
                assert!((light.power(&b) - w).abs() <= 1e-4 * w, "{name}: {} vs {w}", light.power(&b));
            }
        }
    }

    #[test]
    fn rays_start_on_the_light_and_enter_the_scene() {
        let b = scene();
        let (centre, r) = (Vec3::new(1.0, 2.0, 3.0), 3.0f32);
        assert_eq!(scene_sphere(&b), (centre, r));
        let mut rng = Pcg32::new(5, 1);
        for (name, light) in lights() {
            for _ in 0..20_000 {
                let (u_pos, u_dir) = samples(&mut rng);
                let Some(s) = light.sample_le(u_pos, u_dir, &b) else { continue };
                let (o, d) = (s.ray.origin, s.ray.dir);
                assert!((d.length() - 1.0).abs() < 1e-5, "{name}: |dir| = {}", d.length());
                match &light {
                    Emitter::Delta(Light::Point { position, .. } | Light::Spot { position, .. }) => {
                        assert_eq!(o, *position, "{name}");
                        assert_eq!((s.n, s.pdf_pos), (Vec3::ZERO, 1.0), "{name}");
                    }
                    Emitter::Area(area) => {
                        assert!((s.n.length() - 1.0).abs() < 1e-5, "{name}");
                        assert!(s.n.dot(d) >= 0.0, "{name}: leaves from the emitting side");
                        // The ray does not meet the surface it leaves (a
                        // triangle, or a sphere emitting outwards).
                        if let Some(hit) = area.shape.intersect(&s.ray, f32::INFINITY) {
                            panic!("{name}: the ray meets its light at t = {}", hit.t);
                        }
                        match &area.shape {
                            Shape::Sphere(sp) => {
                                let dist = (o - sp.center()).length();
                                assert!((dist - sp.radius()).abs() < 2e-5, "{name}: {dist}");
                                // The outside emits.
                                assert!(s.n.dot(o - sp.center()) > 0.0, "{name}");
                            }
                            Shape::Triangle(_) => {
                                let v = triangle();
                                let nt = (v[1] - v[0]).cross(v[2] - v[0]);
                                let area2 = nt.length();
                                // Barycentrics from sub-triangle areas.
                                let bary: Vec<f32> = (0..3)
                                    .map(|i| (v[(i + 1) % 3] - o).cross(v[(i + 2) % 3] - o).dot(nt) / (area2 * area2))
                                    .collect();
                                assert!(bary.iter().all(|&x| x > -1e-5), "{name}: {bary:?}");
                                let off = (o - v[0]).dot(nt) / area2;
                                assert!(off.abs() < 2e-5, "{name}: {off} off the plane");
                                assert!((bary.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{name}: {bary:?}");
                                if !area.two_sided {
                                    // The front side, or the back when reversed.
                                    assert_eq!(s.n.dot(nt) > 0.0, !area.reverse, "{name}");
                                }
                            }
                            _ => unreachable!(),
                        }
                    }
                    Emitter::Delta(Light::Directional { .. }) | Emitter::Environment(_) => {
                        if let Emitter::Delta(Light::Directional { direction, .. }) = &light {
                            assert_eq!(d, *direction, "{name}");
                        }
                        assert_eq!(s.n, Vec3::ZERO, "{name}");
                        // Outside the sphere, travelling into it, and
                        // crossing it.
                        let to_centre = centre - o;
                        assert!(to_centre.length() >= r * (1.0 - 1e-5), "{name}: {}", to_centre.length());
                        assert!(d.dot(to_centre) > 0.0, "{name}");
                        let miss = (to_centre - to_centre.dot(d) * d).length();
                        assert!(miss <= r * (1.0 + 1e-5), "{name}: passes at {miss}");
                        assert!((s.pdf_pos - 1.0 / (PI * r * r)).abs() < 1e-6, "{name}");
                    }
                }
            }
        }
    }

    #[test]
    fn delta_lights_emit_their_intensity() {
        let b = scene();
        let u = (Vec2::new(0.3, 0.6), Vec2::new(0.2, 0.9));
        let point = Emitter::Delta(Light::point(Vec3::ZERO, Color::new(1.0, 2.0, 3.0), 2.0, Falloff::None).unwrap());
        let s = point.sample_le(u.0, u.1, &b).unwrap();
        assert_eq!((s.l, s.pdf_pos, s.pdf_dir), (Color::new(2.0, 4.0, 6.0), 1.0, 1.0 / (4.0 * PI)));
        // A spot: on the axis and in the blend, what `sample_li` delivers
        // at unit distance with the inverse-square falloff.
        let spot = Light::spot(Vec3::ZERO, -Vec3::Y, Color::ONE, 4.0, 30.0, 10.0, Falloff::InverseSquare).unwrap();
        let e = Emitter::Delta(spot.clone());
        let mut rng = Pcg32::new(9, 9);
        let mut blended = 0;
        for _ in 0..2000 {
            let (up, ud) = samples(&mut rng);
            let Some(s) = e.sample_le(up, ud, &b) else { continue };
            assert!(s.ray.dir.dot(-Vec3::Y) >= 30f32.to_radians().cos() - 1e-5);
            let li = spot.sample_li(s.ray.dir).map_or(Color::ZERO, |x| x.li);
            assert!((s.l - li).abs().max_element() <= 1e-4 * 4.0, "{} vs {}", s.l, li);
            blended += (s.l.x < 4.0) as usize;
        }
        assert!(blended > 0);
        let sun = Emitter::Delta(Light::directional(Vec3::new(0.0, -1.0, 0.0), Color::ONE, 3.0).unwrap());
        let s = sun.sample_le(u.0, u.1, &b).unwrap();
        assert_eq!((s.ray.dir, s.l, s.pdf_dir), (-Vec3::Y, Color::splat(3.0), 1.0));
        // A black light emits nothing.
        let dark = Emitter::Delta(Light::point(Vec3::ZERO, Color::ONE, 0.0, Falloff::None).unwrap());
        assert!(dark.sample_le(u.0, u.1, &b).is_none());
    }

    #[test]
    fn environment_rays_carry_the_radiance_sample_li_sees() {
        let b = scene();
        let ctx = LightSampleContext { p: Vec3::new(1.0, 2.0, 3.0), n: Vec3::ZERO };
        let mut rng = Pcg32::new(21, 4);
        for env in [Environment::Constant(Color::new(0.2, 0.4, 0.6)), image_environment()] {
            let light = Emitter::Environment(env.clone());
            let (mut n, mut differ) = (0, 0);
            for _ in 0..5000 {
                let (u_pos, u_dir) = samples(&mut rng);
                let Some(s) = light.sample_le(u_pos, u_dir, &b) else { continue };
                // The same direction (reversed) and radiance as the light
                // sample with the same u_dir.
                let li = env.sample_li(&ctx, u_dir).unwrap();
                assert!((s.ray.dir + li.wi).length() < 1e-6);
                assert_eq!((s.l, s.pdf_dir), (li.l, li.pdf));
                // le takes the direction of an escaping ray: towards the light.
                n += 1;
                differ += (env.le(-s.ray.dir) != s.l) as usize;
            }
            assert!(n > 4000 && differ <= n / 1000, "{differ} of {n}");
        }
        // An empty or unbounded scene: the unit sphere at the origin.
        let sun = Emitter::Delta(Light::directional(Vec3::X, Color::ONE, 1.0).unwrap());
        for bounds in [Bounds3::EMPTY, Bounds3::INFINITE] {
            let s = sun.sample_le(Vec2::splat(0.5), Vec2::ZERO, &bounds).unwrap();
            assert!((s.ray.origin - -Vec3::X).length() < 1e-6, "{}", s.ray.origin);
            assert!((s.pdf_pos - 1.0 / PI).abs() < 1e-6);
            assert_eq!(sun.pdf_le(s.ray.origin, Vec3::ZERO, s.ray.dir, &bounds), (s.pdf_pos, 1.0));
        }
        // A scene of one point has no disk.
        let point = Bounds3::from_points(Vec3::ONE, Vec3::ONE);
        assert!(sun.sample_le(Vec2::splat(0.5), Vec2::ZERO, &point).is_none());
        assert_eq!(sun.pdf_le(Vec3::ZERO, Vec3::ZERO, Vec3::X, &point).0, 0.0);
    }

    #[test]
    fn area_light_directions_follow_the_emitting_side() {
        let b = scene();
        let one = Emitter::Area(triangle_light(false, false));
        let v = triangle();
        let nt = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let p = (v[0] + v[1] + v[2]) / 3.0;
        let w = (nt + Vec3::new(0.1, 0.2, 0.0)).normalize();
        let cos = w.dot(nt);
        assert!((one.pdf_le(p, nt, w, &b).1 - cos / PI).abs() < 1e-6);
        assert_eq!(one.pdf_le(p, nt, -w, &b).1, 0.0);
        let back = Emitter::Area(triangle_light(false, true));
        assert_eq!(back.pdf_le(p, nt, w, &b).1, 0.0);
        assert!((back.pdf_le(p, nt, -w, &b).1 - cos / PI).abs() < 1e-6);
        let two = Emitter::Area(triangle_light(true, false));
        assert!((two.pdf_le(p, -nt, -w, &b).1 - cos / (2.0 * PI)).abs() < 1e-6);
        assert!((two.pdf_le(p, nt, w, &b).1 - cos / (2.0 * PI)).abs() < 1e-6);
        // Both sides of a two-sided light are sampled, each half the time.
        let mut rng = Pcg32::new(3, 3);
        let mut front = 0;
        for _ in 0..10_000 {
            let (u_pos, u_dir) = samples(&mut rng);
            let s = two.sample_le(u_pos, u_dir, &b).unwrap();
            front += (s.ray.dir.dot(nt) > 0.0) as usize;
            assert_eq!(s.l, Color::splat(2.0));
        }
        assert!((4700..=5300).contains(&front), "{front}");
        // A shape that is not sampled.
        let plane = Emitter::Area(AreaLight {
            shape: Shape::Plane(crate::shapes::Plane::new(Vec3::ZERO, Vec3::Y).unwrap()),
            ..triangle_light(false, false)
        });
        assert!(plane.sample_le(Vec2::splat(0.5), Vec2::splat(0.5), &b).is_none());
        assert_eq!(plane.pdf_le(Vec3::ZERO, Vec3::Y, Vec3::Y, &b), (0.0, 0.0));
    }

    #[test]
    fn emission_images_are_read_at_the_sampled_point() {
        // A checkerboard over the triangle's barycentric uv, on a triangle
        // primitive and on a sphere primitive.
        let texture = Texture::Checker { even: Color::new(1.0, 0.5, 0.25), odd: Color::splat(3.0), scale: 0.1 };
        let tri = Triangle::new(triangle(), None).unwrap();
        let sph = Sphere::new(Vec3::new(0.5, 1.0, -2.0), 0.75).unwrap();
        let cases = [
            (
                Shape::Triangle(tri.clone()),
                Primitive::new(tri, crate::geometry::Transform::IDENTITY, MaterialId::new(0)),
            ),
            (Shape::Sphere(sph.clone()), Primitive::new(sph, crate::geometry::Transform::IDENTITY, MaterialId::new(0))),
        ];
        for (shape, surface) in cases {
            for reverse in [false, true] {
                let image = Arc::new(EmissionImage::new(texture.clone(), surface.clone()));
                let light = Emitter::Area(AreaLight {
                    shape: shape.clone(),
                    radiance: Color::splat(2.0),
                    two_sided: false,
                    reverse,
                    image: Some(image),
                });
                let mut rng = Pcg32::new(8, 8);
                let (mut colours, mut n) = (std::collections::HashSet::new(), 0);
                for _ in 0..2000 {
                    let (u_pos, u_dir) = samples(&mut rng);
                    let s = light.sample_le(u_pos, u_dir, &scene()).expect("every point is found");
                    n += 1;
                    // The uv of the point, from a ray arriving from far away
                    // on the emitting side.
                    let hit = surface.intersect(&Ray::new(s.ray.origin + 0.01 * s.n, -s.n), 1.0).unwrap();
                    let want = 2.0 * texture.evaluate(&TextureContext::new(hit.p, hit.n, hit.uv));
                    assert!((s.l - want).abs().max_element() < 1e-5, "{} vs {want}", s.l);
                    colours.insert(format!("{}", s.l));
                }
                assert_eq!((n, colours.len()), (2000, 2), "{colours:?}");
            }
        }
    }
}
