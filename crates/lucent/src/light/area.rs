//! Area lights: emissive surfaces.
//!
//! An area light is a sphere or a triangle, in world space, with a
//! radiance; the geometry of sampling it is the shape's own (PBRT 4th ed.,
//! §6.1: [`Shape::area`], [`Shape::sample_solid_angle`],
//! [`Shape::pdf_solid_angle`]): a sphere seen from outside is sampled by
//! the cone of directions it subtends, a triangle by the spherical triangle
//! it subtends, each otherwise by area. Every pdf here is with respect to
//! solid angle at the shading point. What is about light stays here: the
//! radiance, which sides emit, the power.
//!
//! A light's radiance may vary over its surface, read from an image by
//! the surface's texture coordinates ([`EmissionImage`], pbrt-v4's
//! `DiffuseAreaLight` with a `filename`, PBRT 4th ed., §12.5.1).

use super::emitter::{LiSample, LightSampleContext};
use crate::color::{luminance, Color};
use crate::geometry::{Ray, Vec2, Vec3};
use crate::mesh::VertexAttributes;
use crate::primitive::Primitive;
use crate::shapes::{Rectangle, Shape, ShapeSample, Sphere};
use crate::texture::{Texture, TextureContext};
use std::f32::consts::PI;
use std::sync::Arc;

/// Radiance that varies over an emitter: `L(p) = radiance · texture(uv(p))`.
///
/// The texture is evaluated at the texture coordinates of the emitting
/// surface itself, the placed primitive: at a ray's hit they are the hit's;
/// for a point drawn by light sampling they are found by intersecting that
/// primitive along the sampled direction (one ray against one primitive;
/// if something of the same primitive lies in front of the sampled point,
/// the shadow ray is blocked anyway).
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionImage {
    /// The texture (an image, typically), multiplied by the light's
    /// [`AreaLight::radiance`].
    pub texture: Texture,
    /// The emitting primitive, in world space through its transform.
    pub surface: Primitive,
    /// The texture's mean over `[0, 1]²`, for the light's power.
    pub mean: Color,
}

impl EmissionImage {
    /// An emission texture on `surface`; its mean is estimated on a 64 × 64
    /// grid of texture coordinates (it only steers which light is sampled).
    pub fn new(texture: Texture, surface: Primitive) -> Self {
        const N: usize = 64;
        let mut sum = Color::ZERO;
        for j in 0..N {
            for i in 0..N {
                let uv = Vec2::new((i as f32 + 0.5) / N as f32, (j as f32 + 0.5) / N as f32);
                sum += texture.evaluate(&TextureContext::new(Vec3::ZERO, Vec3::Z, uv)).max(Color::ZERO);
            }
        }
        Self { texture, surface, mean: sum / (N * N) as f32 }
    }

    fn at(&self, p: Vec3, n: Vec3, uv: Vec2, attributes: VertexAttributes) -> Color {
        self.texture.evaluate(&TextureContext::new(p, n, uv).with_attributes(attributes)).max(Color::ZERO)
    }
}

/// A diffuse emitter: constant radiance over its surface.
///
/// The shape is a [`Shape::Sphere`] or a [`Shape::Triangle`] in world space
/// (the scene builder makes one light per sphere, triangle or mesh face,
/// and refuses planes and stretched spheres). Other shapes are not sampled:
/// a light made of one gives no samples, pdf 0 and (a mesh) no front side.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Where it is: a sphere or a triangle, in world space.
    pub shape: Shape,
    /// Emitted radiance.
    pub radiance: Color,
    /// Whether both sides emit (otherwise only one: the front, or the back
    /// when `reverse`).
    pub two_sided: bool,
    /// Whether a one-sided light emits from its back instead of its front:
    /// the side opposite the shape's own normal (a triangle's winding
    /// normal, a sphere's outward normal), as pbrt-v4's one-sided area
    /// lights under `ReverseOrientation` (PBRT 4th ed., §12.3: the light
    /// emits on the side of the surface normal, which `ReverseOrientation`
    /// flips). No effect when two-sided.
    pub reverse: bool,
    /// Radiance that varies over the surface: `radiance` times this
    /// texture.
    pub image: Option<Arc<EmissionImage>>,
}

impl AreaLight {
    /// The light's rectangle, if it is a rectangle of uniform radiance
    /// (no emission texture): the lights whose samples the path integrator
    /// takes many at a time.
    #[inline]
    pub fn plain_rectangle(&self) -> Option<&Rectangle> {
        match &self.shape {
            Shape::Rectangle(r) if self.image.is_none() => Some(r),
            _ => None,
        }
    }

    /// The light's sphere, if it is a sphere without an emission texture:
    /// the lights whose samples the path integrator computes many at a
    /// time.
    #[inline]
    pub fn plain_sphere(&self) -> Option<&Sphere> {
        match &self.shape {
            Shape::Sphere(s) if self.image.is_none() => Some(s),
            _ => None,
        }
    }

    /// Radiance leaving a point of the light with unit geometric normal `n`
    /// (the shape's own orientation) in direction `w`: towards the side of
    /// `n` (the side opposite `n` when [`AreaLight::reverse`]), or either
    /// side when two-sided.
    #[inline]
    pub fn l(&self, n: Vec3, w: Vec3) -> Color {
        let cos = n.dot(w);
        let emits = if self.reverse { cos < 0.0 } else { cos > 0.0 };
        if self.two_sided || emits {
            self.radiance
        } else {
            Color::ZERO
        }
    }

    /// Radiance leaving the point `p` (texture coordinates `uv`) of the
    /// light in direction `w`, on a surface without vertex attributes: see
    /// [`AreaLight::emitted_at`].
    #[inline]
    pub fn emitted(&self, p: Vec3, uv: Vec2, w: Vec3) -> Color {
        self.emitted_at(p, uv, VertexAttributes::plain(uv), w)
    }

    /// Radiance leaving the point `p` (texture coordinates `uv`, vertex
    /// attributes `attributes`) of the light in direction `w`, with the emitting side ([`AreaLight::l`])
    /// decided by the light's own geometry ([`Shape::front_side`]: a
    /// triangle's winding, a sphere's outside), whatever normal the
    /// intersection reported.
    #[inline]
    pub fn emitted_at(&self, p: Vec3, uv: Vec2, attributes: VertexAttributes, w: Vec3) -> Color {
        let l = if self.two_sided { self.radiance } else { self.l(self.shape.front_side(p), w) };
        match &self.image {
            Some(image) if l != Color::ZERO => l * image.at(p, self.shape.front_side(p), uv, attributes),
            _ => l,
        }
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        self.shape.area()
    }

    /// Emitted power (luminance): a Lambertian emitter of radiance `L`
    /// sends `π L` per unit area from each emitting side, so
    /// `Φ = π · A · lum(L) · (2 if two-sided)` (PBRT 4th ed., §12.3.1).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        let mean = self.image.as_ref().map_or(Color::ONE, |i| i.mean);
        PI * self.area() * luminance(self.radiance * mean) * sides
    }

    /// Sample a direction from `ctx` towards the light with uniform `u` in
    /// `[0, 1)²` ([`Shape::sample_solid_angle`]). `None` when no light
    /// arrives from the sample (the point is on the light, or sees its
    /// non-emitting side). (Always inlined: see
    /// [`Emitter::sample_li`](super::Emitter::sample_li).)
    #[inline(always)]
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LiSample> {
        let s = self.shape.sample_solid_angle(ctx.p, u)?;
        self.sample_li_from(ctx, s)
    }

    /// [`AreaLight::sample_li`] for the sample `s` of the light's shape
    /// (from [`Shape::sample_solid_angle`] at `ctx.p`, or computed as it
    /// would): the direction, radiance and pdf, or `None` where the light
    /// sends nothing towards `ctx`.
    pub fn sample_li_from(&self, ctx: &LightSampleContext, s: ShapeSample) -> Option<LiSample> {
        let (p_light, n_light, pdf) = (s.p, s.n, s.pdf);
        let to = p_light - ctx.p;
        let d = to.length();
        if !(d > 0.0 && pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let wi = to / d;
        let mut l = self.l(n_light, -wi);
        if let (Some(image), true) = (&self.image, l != Color::ZERO) {
            // The texture coordinates of the sampled point: those of the
            // emitting primitive where the sampled direction meets it.
            let hit = image.surface.intersect(&Ray::new(ctx.p, wi), d * (1.0 + 1e-3))?;
            l *= image.at(p_light, n_light, hit.uv, hit.attributes);
        }
        if l == Color::ZERO {
            return None;
        }
        Some(LiSample { l, wi, pdf, p_light: Some(p_light) })
    }

    /// The solid-angle pdf with which [`AreaLight::sample_li`] from `ctx`
    /// picks direction `wi`, which reaches the light at `p_light`
    /// ([`Shape::pdf_solid_angle`]). The same pdf the sampling routine
    /// computed for that direction, whether or not the light emits towards
    /// `ctx` (for a triangle sampled by area the triangle's own normal is
    /// used, so `n_light` is not needed).
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, p_light: Vec3) -> f32 {
        let _ = wi;
        self.shape.pdf_solid_angle(ctx.p, p_light)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;
    use crate::shapes::{triangle_solid_angle, Sphere, Triangle, MAX_SPHERICAL_SAMPLE_AREA, MIN_SPHERICAL_SAMPLE_AREA};

    fn ctx(p: Vec3, n: Vec3) -> LightSampleContext {
        LightSampleContext { p, n }
    }

    fn sphere(center: Vec3, radius: f32) -> Shape {
        Shape::Sphere(Sphere::new(center, radius).unwrap())
    }

    fn triangle(v: [Vec3; 3]) -> Shape {
        Shape::Triangle(Triangle::new(v, None).unwrap())
    }

    /// MC irradiance `E = E[l · max(0, n·wi) / pdf]` at `c` with `m`
    /// samples: (mean, standard error). Also checks that `pdf_li` returns
    /// each sample's pdf.
    fn irradiance(light: &AreaLight, c: &LightSampleContext, m: usize, seed: u64) -> (f64, f64) {
        let mut rng = Pcg32::new(seed, 0);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..m {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let mut x = 0.0f64;
            if let Some(s) = light.sample_li(c, u) {
                assert!((s.wi.length() - 1.0).abs() < 1e-4);
                let pl = s.p_light.expect("area lights are at a point");
                let pdf = light.pdf_li(c, s.wi, pl);
                assert!((pdf - s.pdf).abs() <= 1e-4 * s.pdf, "pdf_li {pdf} vs sample {}", s.pdf);
                x = (s.l.x * s.wi.dot(c.n).max(0.0) / s.pdf) as f64;
            }
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / m as f64;
        let var = (sum2 / m as f64 - mean * mean).max(0.0);
        (mean, (var / m as f64).sqrt())
    }

    #[track_caller]
    fn assert_close(got: (f64, f64), want: f64) {
        let (mean, se) = got;
        assert!((mean - want).abs() <= 5.0 * se + 2e-3 * want.abs(), "MC {mean} ± {se}, expected {want}");
    }

    #[test]
    fn sphere_irradiance_matches_the_analytic_value() {
        // E = π L (r/d)² on a surface facing a sphere of radius r at distance d.
        let (r, d, l) = (0.5f32, 3.0f32, 2.0f32);
        let light = AreaLight {
            shape: sphere(Vec3::new(0.0, 0.0, d), r),
            radiance: Color::splat(l),
            two_sided: false,
            reverse: false,
            image: None,
        };
        let want = (PI * l * (r / d).powi(2)) as f64;
        assert_close(irradiance(&light, &ctx(Vec3::ZERO, Vec3::Z), 50_000, 1), want);
        // A tiny, distant sphere takes the small-angle branch.
        let far = AreaLight { shape: sphere(Vec3::new(0.0, 0.0, 100.0), 0.5), ..light };
        assert_close(
            irradiance(&far, &ctx(Vec3::ZERO, Vec3::Z), 20_000, 2),
            (PI * l * (0.5f32 / 100.0).powi(2)) as f64,
        );
    }

    #[test]
    fn inside_a_sphere_sees_uniform_radiance() {
        // An enclosure of uniform radiance L gives E = π L whatever the normal.
        let light = AreaLight {
            shape: sphere(Vec3::ZERO, 2.0),
            radiance: Color::splat(1.5),
            two_sided: true,
            reverse: false,
            image: None,
        };
        let c = ctx(Vec3::new(0.5, 1.0, -0.3), Vec3::new(1.0, 1.0, 0.0).normalize());
        assert_close(irradiance(&light, &c, 100_000, 3), (PI * 1.5) as f64);
        // One-sided: only the outside emits, so nothing arrives inside.
        let one = AreaLight { two_sided: false, ..light };
        assert_eq!(irradiance(&one, &c, 1000, 4).0, 0.0);
    }

    /// Irradiance from a polygon of radiance `l` at the origin with normal
    /// `n` by Lambert's formula (J. H. Lambert, Photometria, 1760; in the
    /// vector form of Arvo, "Applications of Irradiance Tensors to the
    /// Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995, eq. 7):
    /// `E = (L/2) |Σ_i Θ_i (n · Γ̂_i)|`, with `Θ_i` the angle the edge from
    /// vertex `i` to `i+1` subtends and `Γ̂_i = normalize(a_i × a_{i+1})`
    /// for unit vectors `a_i` towards the vertices. Valid when the polygon
    /// lies wholly above the surface's horizon.
    fn lambert_irradiance(v: &[Vec3], p: Vec3, n: Vec3, l: f32) -> f64 {
        let a: Vec<glam::DVec3> = v.iter().map(|&x| (x - p).as_dvec3().normalize()).collect();
        let n = n.as_dvec3();
        let mut s = 0.0;
        for i in 0..a.len() {
            let (ai, aj) = (a[i], a[(i + 1) % a.len()]);
            let theta = ai.dot(aj).clamp(-1.0, 1.0).acos();
            s += theta * n.dot(ai.cross(aj).normalize());
        }
        0.5 * l as f64 * s.abs()
    }

    #[test]
    fn triangle_irradiance_matches_lamberts_formula_in_both_regimes() {
        let tri = [Vec3::new(-1.0, 2.0, -0.5), Vec3::new(1.5, 2.2, -0.3), Vec3::new(0.2, 2.5, 1.5)];
        // Front faces −y: wind so that the normal points at the origin.
        let front = if (tri[1] - tri[0]).cross(tri[2] - tri[0]).y < 0.0 { tri } else { [tri[0], tri[2], tri[1]] };
        let light = AreaLight {
            shape: triangle(front),
            radiance: Color::splat(3.0),
            two_sided: false,
            reverse: false,
            image: None,
        };
        let n = Vec3::new(0.2, 1.0, 0.1).normalize();
        let spherical = MIN_SPHERICAL_SAMPLE_AREA..=MAX_SPHERICAL_SAMPLE_AREA;
        // Spherical sampling at moderate distance.
        let p = Vec3::ZERO;
        let omega = triangle_solid_angle(front, p);
        assert!(spherical.contains(&omega), "{omega}");
        assert_close(irradiance(&light, &ctx(p, n), 100_000, 5), lambert_irradiance(&front, p, n, 3.0));
        // Area sampling far away: a tiny solid angle.
        let far = Vec3::new(0.0, -150.0, 0.0);
        let omega = triangle_solid_angle(front, far);
        assert!(omega < MIN_SPHERICAL_SAMPLE_AREA, "{omega}");
        assert_close(irradiance(&light, &ctx(far, n), 50_000, 6), lambert_irradiance(&front, far, n, 3.0));
        // Area sampling very close to a large triangle: solid angle near 2π.
        let big = [Vec3::new(-20.0, 1.0, -20.0), Vec3::new(0.0, 1.0, 30.0), Vec3::new(20.0, 1.0, -20.0)];
        let big = if (big[1] - big[0]).cross(big[2] - big[0]).y < 0.0 { big } else { [big[0], big[2], big[1]] };
        let close = Vec3::new(0.0, 0.99, 0.0);
        let omega = triangle_solid_angle(big, close);
        assert!(omega > MAX_SPHERICAL_SAMPLE_AREA, "{omega}");
        let big_light = AreaLight { shape: triangle(big), ..light };
        assert_close(
            irradiance(&big_light, &ctx(close, Vec3::Y), 200_000, 7),
            lambert_irradiance(&big, close, Vec3::Y, 3.0),
        );
    }

    #[test]
    fn one_sided_triangle_is_dark_from_behind() {
        let v = [Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)];
        // Normal of this winding: (2,0,0) × (1,0,1) = (0,-2,0): faces −y.
        let one = AreaLight { shape: triangle(v), radiance: Color::ONE, two_sided: false, reverse: false, image: None };
        let below = ctx(Vec3::ZERO, Vec3::Y);
        let above = ctx(Vec3::new(0.0, 2.0, 0.3), -Vec3::Y);
        assert!(irradiance(&one, &below, 1000, 1).0 > 0.0);
        assert_eq!(irradiance(&one, &above, 1000, 1).0, 0.0);
        assert_eq!(one.emitted(Vec3::new(0.0, 1.0, 0.3), Vec2::ZERO, Vec3::Y), Color::ZERO);
        assert_eq!(one.emitted(Vec3::new(0.0, 1.0, 0.3), Vec2::ZERO, -Vec3::Y), Color::ONE);
        let two = AreaLight { two_sided: true, ..one.clone() };
        assert!(irradiance(&two, &above, 1000, 1).0 > 0.0);
        // Reversed: the back emits, the front is dark.
        let back = AreaLight { reverse: true, ..one.clone() };
        assert_eq!(irradiance(&back, &below, 1000, 1).0, 0.0);
        let (e_back, e_front) = (irradiance(&back, &above, 20_000, 2).0, irradiance(&one, &below, 20_000, 2).0);
        assert!(e_back > 0.0 && e_front > 0.0);
        assert_eq!(back.emitted(Vec3::new(0.0, 1.0, 0.3), Vec2::ZERO, Vec3::Y), Color::ONE);
        assert_eq!(back.emitted(Vec3::new(0.0, 1.0, 0.3), Vec2::ZERO, -Vec3::Y), Color::ZERO);
        assert_eq!(back.l(-Vec3::Y, Vec3::Y), Color::ONE);
        // Two-sided lights ignore it.
        let both = AreaLight { two_sided: true, ..back };
        assert_eq!(both.emitted(Vec3::new(0.0, 1.0, 0.3), Vec2::ZERO, -Vec3::Y), Color::ONE);
    }

    #[test]
    fn reversed_sphere_emits_inwards() {
        // A one-sided sphere reversed lights its inside (uniform radiance L
        // in an enclosure gives E = π L) and not its outside.
        let light = AreaLight {
            shape: sphere(Vec3::ZERO, 2.0),
            radiance: Color::splat(1.5),
            two_sided: false,
            reverse: true,
            image: None,
        };
        let inside = ctx(Vec3::new(0.5, 1.0, -0.3), Vec3::new(1.0, 1.0, 0.0).normalize());
        assert_close(irradiance(&light, &inside, 100_000, 3), (PI * 1.5) as f64);
        assert_eq!(irradiance(&light, &ctx(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z), 1000, 4).0, 0.0);
        assert_eq!(light.power(), AreaLight { reverse: false, ..light.clone() }.power());
    }

    #[test]
    fn power_is_pi_area_radiance() {
        let tri = AreaLight {
            shape: triangle([Vec3::ZERO, Vec3::X, Vec3::Y]),
            radiance: Color::splat(2.0),
            two_sided: false,
            reverse: false,
            image: None,
        };
        assert!((tri.area() - 0.5).abs() < 1e-6);
        assert!((tri.power() - PI * 0.5 * 2.0).abs() < 1e-5);
        let two = AreaLight { two_sided: true, ..tri.clone() };
        assert!((two.power() - 2.0 * tri.power()).abs() < 1e-5);
        let s = AreaLight { shape: sphere(Vec3::ZERO, 1.0), ..tri };
        assert!((s.power() - PI * 4.0 * PI * 2.0).abs() < 1e-3);
    }

    #[test]
    fn degenerate_mesh_faces_are_dark_lights() {
        // The builder keeps a degenerate face as a light, so that face
        // indices and light indices agree: area 0, no samples, pdf 0.
        let flat = AreaLight {
            shape: Shape::Triangle(Triangle::new_unchecked([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X])),
            radiance: Color::ONE,
            two_sided: true,
            reverse: false,
            image: None,
        };
        assert_eq!(flat.power(), 0.0);
        let c = ctx(Vec3::new(0.5, 1.0, 0.0), -Vec3::Y);
        assert_eq!(irradiance(&flat, &c, 100, 1).0, 0.0);
        assert_eq!(flat.pdf_li(&c, -Vec3::Y, Vec3::new(0.5, 0.0, 0.0)), 0.0);
    }
}
