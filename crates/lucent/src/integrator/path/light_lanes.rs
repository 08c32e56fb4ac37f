//! Next-event estimation across lanes, for the commonest vertex of interior
//! scenes: a diffuse surface sampling a rectangle light.
//!
//! The light stage of [`super::lanes`] gathers the lanes whose BSDF is a
//! plain diffuse lobe and whose light pick is a rectangle area light
//! (without an emission texture, in a scene without media) into structure
//! of arrays: the shading point, the directions and albedo, the throughput
//! and the light sample. The rectangle is sampled for all of them at once
//! ([`Rectangle::sample_solid_angle_lanes`]: the spherical rectangle of
//! Ureña et al. for the near lanes, the area for the far ones), then the
//! BSDF's value, both pdfs and the power heuristic are computed lane by
//! lane in loops the compiler vectorises. Only the shadow rays are traced
//! one lane at a time. Every other lane takes the scalar
//! [`PathIntegrator::sample_light`].
//!
//! The kernels run the scalar functions' operations in the same order, so
//! each lane's light sample is the scalar one bit for bit (a test compares
//! them on random lanes; renders are byte-identical).

use super::lanes::LightStage;
use super::{occluded, power_heuristic, DirectLighting};
use crate::bsdf::Bxdf;
use crate::color::Color;
use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{group, set_group, Vec3Lanes, GROUP, LANES};
use crate::interaction::SurfaceInteraction;
use crate::light::{AreaLight, Emitter};
use crate::scene::Scene;
use crate::shapes::Rectangle;
use std::f32::consts::FRAC_1_PI;

/// The lanes of one light stage that sample one rectangle light together.
pub(super) struct RectangleLanes<'a> {
    /// The light's index among the scene's lights, its pick probability,
    /// the light and its rectangle: those of the first lane taken.
    light: Option<(usize, f32, &'a AreaLight, &'a Rectangle)>,
    /// The lanes taken, near the rectangle and far from it
    /// ([`Rectangle::near`]).
    near: [u8; LANES],
    near_len: usize,
    far: [u8; LANES],
    far_len: usize,
    /// The kernel's lanes (near ones first), inputs and outputs, kept from
    /// one stage to the next so that they are not cleared each time.
    lanes: [u8; LANES],
    input: Inputs,
    out: Outputs,
}

impl<'a> RectangleLanes<'a> {
    /// No lanes.
    pub(super) fn new() -> Self {
        Self {
            light: None,
            near: [0; LANES],
            near_len: 0,
            far: [0; LANES],
            far_len: 0,
            lanes: [0; LANES],
            input: Inputs::ZERO,
            out: Outputs::ZERO,
        }
    }

    /// No lanes again, for the next stage.
    pub(super) fn clear(&mut self) {
        (self.light, self.near_len, self.far_len) = (None, 0, 0);
    }

    /// Take `lane`, a diffuse vertex (at `si`, with `pick`, the index and
    /// probability of the light its sample picked), if its light sample
    /// can run in the kernel; `false` leaves it to the scalar
    /// [`PathIntegrator::sample_light`].
    #[inline]
    pub(super) fn take(
        &mut self,
        scene: &'a Scene,
        lane: u8,
        si: &SurfaceInteraction,
        (index, pmf): (usize, f32),
    ) -> bool {
        let lights = scene.light_set();
        match self.light {
            Some((taken, ..)) if taken != index => return false,
            Some(_) => {}
            None => {
                let Emitter::Area(area) = &lights.emitters()[index] else { return false };
                let Some(rect) = area.plain_rectangle() else { return false };
                self.light = Some((index, pmf, area, rect));
            }
        }
        let Some((.., rect)) = self.light else { return false };
        if rect.near(si.p) {
            self.near[self.near_len] = lane;
            self.near_len += 1;
        } else {
            self.far[self.far_len] = lane;
            self.far_len += 1;
        }
        true
    }

    /// Next-event estimation for the lanes taken: each lane's light
    /// sample, weighed and, where it carries light, tested with a shadow
    /// ray; what it finds is added to the lane's path.
    pub(super) fn estimate(&mut self, stage: &mut LightStage) {
        let LightStage { integrator, scene, ref mut paths, hits, bsdfs, u, ref mut stats, ref mut interfaces } = *stage;
        let Some((_, pmf, area, rect)) = self.light else { return };
        let n = self.near_len + self.far_len;
        // Gather the lanes, near ones first.
        let (lanes, input, out) = (&mut self.lanes, &mut self.input, &mut self.out);
        let taken = self.near[..self.near_len].iter().chain(&self.far[..self.far_len]);
        for (k, &lane) in taken.enumerate() {
            let i = lane as usize;
            let (Some(si), Some(bsdf)) = (&hits[i], &bsdfs[i]) else { unreachable!("a lane taken has a vertex") };
            let Bxdf::Diffuse(diffuse) = bsdf.bxdf() else { unreachable!("a lane taken is diffuse") };
            lanes[k] = lane;
            input.o.set(k, si.p);
            input.wo.set(k, -paths[i].ray.dir);
            input.ns.set(k, bsdf.frame().z);
            input.r.set(k, diffuse.r);
            input.beta.set(k, paths[i].beta);
            (input.u[0][k], input.u[1][k]) = (u[i].point.x, u[i].point.y);
        }
        let kernel = Kernel { direct: integrator.direct, pmf, area, rect, near: self.near_len, n };
        estimate_lanes_any(&kernel, input, out);
        for (k, &lane) in lanes.iter().enumerate().take(n) {
            if !out.shadow[k] {
                continue;
            }
            let i = lane as usize;
            let Some(si) = &hits[i] else { continue };
            stats.shadow += 1;
            if occluded(scene, si, Some(out.p_light.get(k)), out.wi.get(k), interfaces) {
                continue;
            }
            let path = &mut paths[i];
            path.radiance += integrator.contribution(out.direct.get(k), path.any_non_specular);
        }
    }
}

/// What the kernel needs of each lane.
struct Inputs {
    /// The shading point.
    o: Vec3Lanes,
    /// Towards where the path came from (unit).
    wo: Vec3Lanes,
    /// The shading normal.
    ns: Vec3Lanes,
    /// The diffuse albedo.
    r: Vec3Lanes,
    /// The path throughput.
    beta: Vec3Lanes,
    /// The light sample's 2D value.
    u: [[f32; LANES]; 2],
}

impl Inputs {
    const ZERO: Self = Self {
        o: Vec3Lanes::ZERO,
        wo: Vec3Lanes::ZERO,
        ns: Vec3Lanes::ZERO,
        r: Vec3Lanes::ZERO,
        beta: Vec3Lanes::ZERO,
        u: [[0.0; LANES]; 2],
    };
}

/// What the kernel finds for each lane.
struct Outputs {
    /// Whether the light sample carries light, so that a shadow ray
    /// decides.
    shadow: [bool; LANES],
    /// The sampled point of the light, and the unit direction to it.
    p_light: Vec3Lanes,
    wi: Vec3Lanes,
    /// The throughput times the MIS-weighted estimate, if unoccluded.
    direct: Vec3Lanes,
    /// The light sample's solid-angle pdf.
    pdf: [f32; LANES],
}

impl Outputs {
    const ZERO: Self = Self {
        shadow: [false; LANES],
        p_light: Vec3Lanes::ZERO,
        wi: Vec3Lanes::ZERO,
        direct: Vec3Lanes::ZERO,
        pdf: [0.0; LANES],
    };
}

/// What one call of [`estimate_lanes`] is about: the light and how it is
/// weighed, and which lanes.
#[derive(Clone, Copy)]
struct Kernel<'a> {
    /// How the integrator combines light and BSDF sampling.
    direct: DirectLighting,
    /// The probability of picking the light.
    pmf: f32,
    /// The light and its rectangle.
    area: &'a AreaLight,
    rect: &'a Rectangle,
    /// Lanes `0..near` are near the rectangle ([`Rectangle::near`]),
    /// lanes `near..n` far from it.
    near: usize,
    n: usize,
}

/// [`estimate_lanes`] in the build for this CPU.
fn estimate_lanes_any(kernel: &Kernel, input: &Inputs, out: &mut Outputs) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { estimate_lanes_avx2(kernel, input, out) },
        _ => estimate_lanes(kernel, input, out),
    }
}

/// [`estimate_lanes`] compiled for AVX2: eight lanes to a register.
///
/// # Safety
/// The CPU must have AVX2 and FMA. (FMA only makes the instructions
/// available: Rust never fuses a multiplication and an addition itself, so
/// the values are the portable build's.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn estimate_lanes_avx2(kernel: &Kernel, input: &Inputs, out: &mut Outputs) {
    estimate_lanes(kernel, input, out);
}

/// The kernel: the light sample of lanes `0..n` (the first `near` near
/// the rectangle), each weighed as [`PathIntegrator::sample_light`] weighs
/// it for a diffuse BSDF, times the lane's throughput.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn estimate_lanes(kernel: &Kernel, input: &Inputs, out: &mut Outputs) {
    let Kernel { direct, pmf, area, rect, near, n } = *kernel;
    rect.sample_solid_angle_lanes(&input.o, &input.u, near, n, &mut out.p_light, &mut out.pdf);
    let pdf = &out.pdf;
    let radiance = area.radiance;
    let nl = rect.normal();
    // `AreaLight::sample_li` gives `None` for a black light, and the
    // integrator skips a light sample whose radiance is not positive.
    let max = radiance.max_element();
    let light_ok = radiance != Color::ZERO && (max > 0.0 || max.is_nan());
    let mis = direct != DirectLighting::LightsOnly;
    let (o, ns, wo, r, beta) = (&input.o, &input.ns, &input.wo, &input.r, &input.beta);
    // Lane by lane in scalar arithmetic, so that the loop vectorises;
    // each line is the `Vec3`/`Color` operation it replaces, in its order.
    // Conditions are selects and bitwise `&`/`|` of comparisons, never
    // branches, so that the loop has one path for all lanes.
    // The lanes a [`GROUP`] at a time, each group's values in fixed-size
    // local arrays, so that every group is vector code (a loop over the
    // count would leave up to 31 lanes to a scalar remainder).
    let (two_sided, reverse) = (area.two_sided, area.reverse);
    for c in (0..n.min(LANES).div_ceil(GROUP)).map(|g| g * GROUP) {
        let ([plx, ply, plz], [ox, oy, oz], pdf) = (out.p_light.group(c), o.group(c), group(pdf, c));
        let ([nsx, nsy, nsz], [wox, woy, woz]) = (ns.group(c), wo.group(c));
        let ([rx, ry, rz], [bx, by, bz]) = (r.group(c), beta.group(c));
        let (mut shadow, mut wi, mut value) = ([false; GROUP], [[0.0; GROUP]; 3], [[0.0; GROUP]; 3]);
        for j in 0..GROUP {
            // `AreaLight::sample_li`: the direction, and whether the light
            // emits along it.
            let (tx, ty, tz) = (plx[j] - ox[j], ply[j] - oy[j], plz[j] - oz[j]);
            let d = (tx * tx + ty * ty + tz * tz).sqrt();
            let ok = (d > 0.0) & (pdf[j] > 0.0) & pdf[j].is_finite();
            let (wx, wy, wz) = (tx / d, ty / d, tz / d);
            let cos = nl.x * -wx + nl.y * -wy + nl.z * -wz;
            let emits = two_sided | (reverse & (cos < 0.0)) | (!reverse & (cos > 0.0));
            // The diffuse BSDF in the shading frame: only the local z of
            // both directions matters.
            let wo_z = wox[j] * nsx[j] + woy[j] * nsy[j] + woz[j] * nsz[j];
            let wi_z = wx * nsx[j] + wy * nsy[j] + wz * nsz[j];
            let same_side = wo_z * wi_z > 0.0;
            let c = wi_z.abs();
            let (fx, fy, fz) = if same_side {
                (rx[j] * FRAC_1_PI * c, ry[j] * FRAC_1_PI * c, rz[j] * FRAC_1_PI * c)
            } else {
                (0.0 * c, 0.0 * c, 0.0 * c)
            };
            let f_max = fx.max(fy).max(fz);
            let p_light = pmf * pdf[j];
            let p_bsdf = if same_side { c * FRAC_1_PI } else { 0.0 };
            let w = power_heuristic(p_light, p_bsdf) / p_light;
            let (ax, ay, az) = (fx * radiance.x, fy * radiance.y, fz * radiance.z);
            let (vx, vy, vz) = if mis { (ax * w, ay * w, az * w) } else { (ax / p_light, ay / p_light, az / p_light) };
            shadow[j] = ok & emits & light_ok & ((f_max > 0.0) | f_max.is_nan());
            (wi[0][j], wi[1][j], wi[2][j]) = (wx, wy, wz);
            (value[0][j], value[1][j], value[2][j]) = (bx[j] * vx, by[j] * vy, bz[j] * vz);
        }
        set_group(&mut out.shadow, c, shadow);
        out.wi.set_group(c, wi);
        out.direct.set_group(c, value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{BxDF, DiffuseBxdf};
    use crate::geometry::Vec3;
    use crate::light::LightSampleContext;
    use crate::sampling::Pcg32;
    use crate::shapes::Shape;
    use glam::Vec2;

    /// A random rectangle (edges orthogonal, of any orientation and size).
    fn rectangle(rng: &mut Pcg32) -> Rectangle {
        let mut v = || Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        let (corner, a, b) = (4.0 * v(), v(), v());
        let ex = a.normalize() * (0.05 + 2.0 * a.length());
        let ey = ex.cross(b).normalize() * (0.05 + 2.0 * b.length());
        Rectangle::new(corner, ex, ey).unwrap()
    }

    /// Points around `rect`: near and far, in its plane, on its corner.
    fn point(rng: &mut Pcg32, rect: &Rectangle, k: usize) -> Vec3 {
        let scale = [0.1, 1.0, 3.0, 20.0][k % 4];
        let p = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * scale;
        match k % 23 {
            // In the rectangle's plane.
            0 => {
                let n = rect.normal();
                p - n * n.dot(p - rect.sample_area(Vec2::new(0.3, 0.6)).unwrap().p)
            }
            // On a corner.
            1 => rect.sample_area(Vec2::ZERO).unwrap().p,
            _ => p,
        }
    }

    /// The lane kernels give the scalar functions' values bit for bit:
    /// [`Rectangle::sample_solid_angle_lanes`] those of
    /// [`Rectangle::sample_solid_angle`], and [`estimate_lanes`] those of
    /// [`PathIntegrator::sample_light`]'s arithmetic (the light sample of
    /// [`AreaLight::sample_li`], the diffuse BSDF's value and pdf, the
    /// power heuristic) before its shadow ray, over random rectangles,
    /// points, normals and samples, in batches of 1 to 64 lanes.
    #[test]
    fn lane_kernels_equal_the_scalar_light_sample() {
        let mut rng = Pcg32::new(7, 3);
        let mut lanes_checked = 0;
        for batch in 0..400 {
            let rect = rectangle(&mut rng);
            let n = 1 + batch % LANES;
            let mut input = Inputs::ZERO;
            // Near lanes first, as the light stage gathers them.
            let mut points: Vec<Vec3> = (0..n).map(|k| point(&mut rng, &rect, k)).collect();
            points.sort_by_key(|&p| !rect.near(p));
            let near = points.iter().filter(|&&p| rect.near(p)).count();
            for (k, &p) in points.iter().enumerate() {
                input.o.set(k, p);
                let mut unit = || Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
                input.wo.set(k, unit());
                input.ns.set(k, unit());
                input.r.set(k, Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()));
                input.beta.set(k, Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 3.0);
                (input.u[0][k], input.u[1][k]) = (rng.uniform(), rng.uniform());
            }
            let area = AreaLight {
                shape: Shape::Rectangle(rect.clone()),
                radiance: Color::new(17.0, 12.0, 4.0),
                two_sided: batch % 5 == 0,
                reverse: batch % 7 == 0,
                image: None,
            };
            let pmf = [1.0, 0.25, 0.7][batch % 3];
            let direct = if batch % 4 == 0 { DirectLighting::LightsOnly } else { DirectLighting::Mis };
            // The portable build, and the build for this CPU.
            let kernel = Kernel { direct, pmf, area: &area, rect: &rect, near, n };
            let mut out = Outputs::ZERO;
            estimate_lanes(&kernel, &input, &mut out);
            let mut out_cpu = Outputs::ZERO;
            estimate_lanes_any(&kernel, &input, &mut out_cpu);
            assert_eq!(out.shadow, out_cpu.shadow);
            for k in (0..n).filter(|&k| out.shadow[k]) {
                let lane = |o: &Outputs| (o.p_light.get(k), o.wi.get(k), o.direct.get(k));
                assert_eq!(lane(&out), lane(&out_cpu), "lane {k} of {n}");
            }
            // Lane by lane, the scalar functions.
            let mut sampled = Outputs::ZERO;
            rect.sample_solid_angle_lanes(&input.o, &input.u, near, n, &mut sampled.p_light, &mut sampled.pdf);
            for k in 0..n {
                let (o, u) = (input.o.get(k), Vec2::new(input.u[0][k], input.u[1][k]));
                let scalar = rect.sample_solid_angle(o, u);
                let (p, pdf) = scalar.map_or((None, 0.0), |s| (Some(s.p), s.pdf));
                assert_eq!(sampled.pdf[k].to_bits(), pdf.to_bits(), "pdf of lane {k} of {n}, from {o}");
                if let Some(p) = p {
                    assert_eq!(sampled.p_light.get(k), p, "point of lane {k} of {n}, from {o}");
                }
                let bxdf = DiffuseBxdf { r: input.r.get(k) };
                let frame = crate::geometry::Frame::from_z(input.ns.get(k));
                let wo = input.wo.get(k);
                let expected = area.sample_li(&LightSampleContext { p: o, n: Vec3::ZERO }, u).and_then(|ls| {
                    if ls.pdf <= 0.0 || ls.l.max_element() <= 0.0 {
                        return None;
                    }
                    let (wo_l, wi_l) = (frame.to_local(wo), frame.to_local(ls.wi));
                    let f = bxdf.f(wo_l, wi_l) * wi_l.z.abs();
                    if f.max_element() <= 0.0 {
                        return None;
                    }
                    let p_light = pmf * ls.pdf;
                    let value = if direct == DirectLighting::LightsOnly {
                        f * ls.l / p_light
                    } else {
                        f * ls.l * (power_heuristic(p_light, bxdf.pdf(wo_l, wi_l)) / p_light)
                    };
                    Some((ls.p_light.unwrap(), ls.wi, input.beta.get(k) * value))
                });
                assert_eq!(out.shadow[k], expected.is_some(), "lane {k} of {n}, from {o}");
                if let Some((p, wi, d)) = expected {
                    assert_eq!((out.p_light.get(k), out.wi.get(k), out.direct.get(k)), (p, wi, d), "lane {k} of {n}");
                    lanes_checked += 1;
                }
            }
        }
        // Most lanes see the light.
        assert!(lanes_checked > 2000, "{lanes_checked}");
    }
}
