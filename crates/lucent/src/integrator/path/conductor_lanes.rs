//! The scatter stage across lanes, for rough conductors: the glossy metals
//! of the Veach MIS scene and of glass-and-metal.
//!
//! The lanes whose BSDF is a rough [`ConductorBxdf`] with the exact Fresnel
//! equations (a complex index, given or from pbrt-v4's `reflectance`) are
//! gathered into structure of arrays, and the kernel runs for all of them
//! at once what the scalar `ConductorBxdf::sample_f` and
//! `Bsdf::sample_f` run for one:
//!
//! 1. `wo` into the shading frame, mirrored onto the upper side;
//! 2. a microfacet normal visible from `wo` ([`TrowbridgeReitz::sample_wm`],
//!    Heitz 2018), and `wo` reflected about it;
//! 3. its density `D_wo(wm) / (4 |wo·wm|)` ([`TrowbridgeReitz::d_visible`])
//!    and the Torrance–Sparrow value `D G F / (4 cos θo cos θi)` with the
//!    half vector of the two directions (PBRT 4th ed., eq. 9.28 and 9.33),
//!    the Fresnel term one RGB channel of all lanes at a time
//!    ([`fr_complex_lanes`]);
//! 4. the direction back into world space;
//!
//! then the rest of the scatter stage that every kernel shares
//! ([`super::scatter_lanes::continue_group`]). Every line is the operation of the scalar code it
//! replaces, in the same order, so each lane's new path state is the scalar
//! stage's bit for bit (a test compares them over random lanes). Mirrors,
//! Schlick's Fresnel and every other lobe keep the scalar code.
//!
//! [`TrowbridgeReitz::sample_wm`]: crate::bsdf::TrowbridgeReitz::sample_wm
//! [`TrowbridgeReitz::d_visible`]: crate::bsdf::TrowbridgeReitz::d_visible

use super::scatter_lanes::{GroupSample, Inputs, LobeLanes, Outputs, ScatterLanes, ScatterSet};
use crate::bsdf::fresnel::fr_complex_lanes;
use crate::bsdf::{reflectance_to_complex_ior, ConductorBxdf, ConductorFresnel};
use crate::geometry::{group, sin_cos_lane, Vec3Lanes, GROUP, LANES};
use std::f32::consts::PI;

/// The rough conductor lanes of one scatter stage.
pub(super) type ConductorLanes = ScatterLanes<ConductorLobes>;

/// The rough conductor lobes of a kernel's lanes.
pub(super) struct ConductorLobes {
    /// The roughness along the shading frame's x and y.
    alpha_x: [f32; LANES],
    alpha_y: [f32; LANES],
    /// The complex index `eta + i·k` of each channel.
    eta: Vec3Lanes,
    k: Vec3Lanes,
}

impl ConductorLanes {
    /// No lanes.
    pub(super) fn new() -> Self {
        Self {
            set: ScatterSet::EMPTY,
            lobes: ConductorLobes {
                alpha_x: [0.0; LANES],
                alpha_y: [0.0; LANES],
                eta: Vec3Lanes::ZERO,
                k: Vec3Lanes::ZERO,
            },
        }
    }

    /// Whether the kernel takes `conductor`: a rough one with the exact
    /// Fresnel equations.
    #[inline]
    pub(super) fn takes(conductor: &ConductorBxdf) -> bool {
        !conductor.distrib.effectively_smooth() && !matches!(conductor.fresnel, ConductorFresnel::Schlick { .. })
    }
}

/// Smith's `Λ(w)` of the GGX distribution (`TrowbridgeReitz::lambda`) for
/// a direction with local coordinates `(x, y, z)`: `(√(1 + α² tan²θ) −
/// 1)/2`, infinite at grazing.
#[inline(always)]
fn lambda(x: f32, y: f32, z: f32, ax: f32, ay: f32) -> f32 {
    let z2 = z * z;
    let (sx, sy) = (x * ax, y * ay);
    let a2_tan2 = (sx * sx + sy * sy) / z2;
    let l = 0.5 * ((1.0 + a2_tan2).sqrt() - 1.0);
    if z2 == 0.0 {
        f32::INFINITY
    } else {
        l
    }
}

/// The GGX density `D(wm)` (`TrowbridgeReitz::d`): `1 / (π αx αy (x²/αx²
/// + y²/αy² + z²)²)`, zero on the lower hemisphere.
#[inline(always)]
fn d(x: f32, y: f32, z: f32, ax: f32, ay: f32) -> f32 {
    let (sx, sy) = (x / ax, y / ay);
    let t = sx * sx + sy * sy + z * z;
    let d = 1.0 / (PI * ax * ay * t * t);
    if z <= 0.0 {
        0.0
    } else {
        d
    }
}

impl LobeLanes for ConductorLobes {
    type Bxdf = ConductorBxdf;

    /// The roughness, and the complex index (pbrt-v4's `reflectance`
    /// turned into one here, once); for a conductor that
    /// [`ConductorLanes::takes`].
    #[inline(always)]
    fn set(&mut self, k: usize, conductor: &ConductorBxdf) {
        self.alpha_x[k] = conductor.distrib.alpha_x();
        self.alpha_y[k] = conductor.distrib.alpha_y();
        let (eta, kappa) = match conductor.fresnel {
            ConductorFresnel::Complex { eta, k } => (eta, k),
            ConductorFresnel::Reflectance { r } => reflectance_to_complex_ior(r),
            ConductorFresnel::Schlick { .. } => unreachable!("the kernel does not take Schlick's Fresnel"),
        };
        self.eta.set(k, eta);
        self.k.set(k, kappa);
    }

    /// The disk's radius and angle for `sample_wm`, then the angle's sine
    /// and cosine ([`sin_cos_lane`]: the angle is within `[0, 2π]`).
    #[inline(always)]
    fn prepare(&self, n: usize, input: &Inputs, out: &mut Outputs) {
        let whole = (n.div_ceil(GROUP) * GROUP).min(LANES);
        for k in 0..whole {
            out.radius[k] = input.u[0][k].sqrt();
            out.theta[k] = 2.0 * PI * input.u[1][k];
        }
        for k in 0..whole {
            (out.sin[k], out.cos[k]) = sin_cos_lane(out.theta[k]);
        }
    }

    /// `ConductorBxdf::sample_f` of each lane of the group, through
    /// `Bsdf::sample_f`'s frames.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn sample_group(&self, c: usize, input: &Inputs, out: &Outputs) -> GroupSample {
        let (radius, cos, sin) = (group(&out.radius, c), group(&out.cos, c), group(&out.sin, c));
        let ([fxx, fxy, fxz], [fyx, fyy, fyz], [fzx, fzy, fzz]) =
            (input.fx.group(c), input.fy.group(c), input.fz.group(c));
        let [wox, woy, woz] = input.wo.group(c);
        let (alpha_x, alpha_y) = (group(&self.alpha_x, c), group(&self.alpha_y, c));
        let mut s = GroupSample::ZERO;
        // The Fresnel term's cosine, and the factor `D G / (4 cos θo cos
        // θi)` it multiplies.
        let (mut cos_f, mut scale) = ([0.0; GROUP], [0.0; GROUP]);
        for j in 0..GROUP {
            let (ax, ay) = (alpha_x[j], alpha_y[j]);
            // `Frame::to_local`, then the upper side (`flip_z`).
            let ox = wox[j] * fxx[j] + woy[j] * fxy[j] + woz[j] * fxz[j];
            let oy = wox[j] * fyx[j] + woy[j] * fyy[j] + woz[j] * fyz[j];
            let wo_z = wox[j] * fzx[j] + woy[j] * fzy[j] + woz[j] * fzz[j];
            let lower = wo_z < 0.0;
            let oz = if lower { -wo_z } else { wo_z };

            // `sample_wm`: wo stretched to the unit-roughness configuration
            // (`normalize_or(Vec3::Z)`: times the reciprocal length).
            let (hx, hy, hz) = (ax * ox, ay * oy, oz);
            let rcp = 1.0 / (hx * hx + hy * hy + hz * hz).sqrt();
            let ok = rcp.is_finite() & (rcp > 0.0);
            let (hx, hy, hz) = if ok { (hx * rcp, hy * rcp, hz * rcp) } else { (0.0, 0.0, 1.0) };
            let (hx, hy, hz) = if hz < 0.0 { (-hx, -hy, -hz) } else { (hx, hy, hz) };
            // A frame around it with t1 horizontal.
            let len2 = hx * hx + hy * hy;
            let len = len2.sqrt();
            let (t1x, t1y, t1z) = if len2 > 0.0 { (-hy / len, hx / len, 0.0 / len) } else { (1.0, 0.0, 0.0) };
            // `wh.cross(t1)`.
            let (t2x, t2y, t2z) = (hy * t1z - hz * t1y, hz * t1x - hx * t1z, hx * t1y - hy * t1x);
            // The disk point, its far half squashed onto the ellipse.
            let (p1, p2) = (radius[j] * cos[j], radius[j] * sin[j]);
            let sq = 0.5 * (1.0 + hz);
            let p2 = (1.0 - sq) * (1.0 - p1 * p1).max(0.0).sqrt() + sq * p2;
            // Lifted to the hemisphere around wh, then unstretched.
            let lift = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
            let nx = p1 * t1x + p2 * t2x + lift * hx;
            let ny = p1 * t1y + p2 * t2y + lift * hy;
            let nz = p1 * t1z + p2 * t2z + lift * hz;
            let (mx, my, mz) = (ax * nx, ay * ny, nz.max(1e-6));
            let m_len = (mx * mx + my * my + mz * mz).sqrt();
            let (mx, my, mz) = (mx / m_len, my / m_len, mz / m_len);

            // `reflect(wo, wm)`.
            let o_m = ox * mx + oy * my + oz * mz;
            let (ix, iy, iz) = (-ox + 2.0 * o_m * mx, -oy + 2.0 * o_m * my, -oz + 2.0 * o_m * mz);

            // The pdf: `d_visible(wo, wm) / (4 |wo·wm|)`, where
            // `d_visible = G1(wo)/cos θo · D(wm) · (wo·wm)` (zero unless
            // wo·wm > 0).
            let lambda_o = lambda(ox, oy, oz, ax, ay);
            let g1 = 1.0 / (1.0 + lambda_o);
            let d_visible = g1 / oz * d(mx, my, mz, ax, ay) * o_m;
            let d_visible = if o_m <= 0.0 { 0.0 } else { d_visible };
            let pdf = d_visible / (4.0 * o_m.abs());

            // `f_upper(wo, wi)`: the half vector of the two directions.
            let (hx, hy, hz) = (ox + ix, oy + iy, oz + iz);
            let h2 = hx * hx + hy * hy + hz * hz;
            let h_len = h2.sqrt();
            let (hx, hy, hz) = (hx / h_len, hy / h_len, hz / h_len);
            let g = 1.0 / (1.0 + lambda_o + lambda(ix, iy, iz, ax, ay));
            let dg = d(hx, hy, hz, ax, ay) * g / (4.0 * oz * iz);
            let upper = (oz > 0.0) & (iz > 0.0) & (h2 != 0.0);
            scale[j] = if upper { dg } else { 0.0 };
            cos_f[j] = (ox * hx + oy * hy + oz * hz).abs();

            s.pdf[j] = pdf;
            s.valid[j] = (wo_z != 0.0) & (iz > 0.0) & (pdf > 0.0) & pdf.is_finite();
            // Back to wo's side (`flip_z`), then `Frame::from_local`.
            let iz = if lower { -iz } else { iz };
            s.wi[0][j] = fxx[j] * ix + fyx[j] * iy + fzx[j] * iz;
            s.wi[1][j] = fxy[j] * ix + fyy[j] * iy + fzy[j] * iz;
            s.wi[2][j] = fxz[j] * ix + fyz[j] * iy + fzz[j] * iz;
        }
        // `fr_conductor`, one channel of the group at a time, times the
        // factor (zero where the directions are not both above).
        for (axis, (eta, k)) in [
            (group(&self.eta.x, c), group(&self.k.x, c)),
            (group(&self.eta.y, c), group(&self.k.y, c)),
            (group(&self.eta.z, c), group(&self.k.z, c)),
        ]
        .into_iter()
        .enumerate()
        {
            let fresnel = fr_complex_lanes(cos_f, eta, k);
            for j in 0..GROUP {
                s.f[axis][j] = fresnel[j] * scale[j];
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::super::scatter_lanes::tests::{random_vertex, scatter_and_check, Lane};
    use super::*;
    use crate::bsdf::{Bsdf, Bxdf, TrowbridgeReitz};
    use crate::color::Color;
    use crate::geometry::Vec2;
    use crate::sampling::Pcg32;
    use crate::sampling::VertexSamples;

    /// A random lane with a rough conductor: grazing and lower-side `wo`,
    /// anisotropic and very rough or nearly smooth lobes, both kinds of
    /// Fresnel index, samples on the square's edges.
    fn lane(rng: &mut Pcg32, k: usize) -> Lane {
        let (mut path, si) = random_vertex(rng, k);
        let alpha = [0.002, 0.05, 0.3, 0.9, 3.0][k % 5] * (0.5 + rng.uniform());
        let distrib = match k % 3 {
            0 => TrowbridgeReitz::new(alpha),
            1 => TrowbridgeReitz::anisotropic(alpha, alpha * (0.1 + 2.0 * rng.uniform())),
            _ => TrowbridgeReitz::anisotropic(1e-4, alpha.max(2e-3)),
        };
        let color = |s: f32, rng: &mut Pcg32| Color::new(rng.uniform(), rng.uniform(), rng.uniform()) * s;
        let fresnel = if k.is_multiple_of(4) {
            ConductorFresnel::Reflectance { r: color(1.0, rng) }
        } else {
            ConductorFresnel::Complex { eta: color(2.0, rng) + Color::splat(0.05), k: color(5.0, rng) }
        };
        let bsdf = Bsdf::new(si.ns, si.dpdu, Bxdf::Conductor(ConductorBxdf { fresnel, distrib }));
        let mut dir_u = Vec2::new(rng.uniform(), rng.uniform());
        match k % 7 {
            0 => dir_u = Vec2::ZERO,
            1 => dir_u = Vec2::new(dir_u.x, 0.0),
            2 => dir_u = Vec2::new(0.999_999_9, dir_u.y),
            _ => {}
        }
        match k % 11 {
            // `wo` in the shading plane, and nearly so.
            0 => path.ray.dir = bsdf.frame().x,
            1 => path.ray.dir = (bsdf.frame().x + 1e-4 * bsdf.frame().z).normalize(),
            _ => {}
        }
        let u = VertexSamples { light: 0.0, point: Vec2::ZERO, lobe: rng.uniform(), dir: dir_u, rr: rng.uniform() };
        (path, si, bsdf, u)
    }

    /// The kernel gives each lane the path state that the scalar scatter
    /// stage gives it, bit for bit, over random lanes in batches of 1 to
    /// 64; and the portable build equals the build for this CPU.
    #[test]
    fn conductor_lanes_equal_the_scalar_scatter() {
        let mut rng = Pcg32::new(17, 3);
        let (mut went_on, mut ended) = (0, 0);
        for batch in 0..400 {
            let n = 1 + batch % LANES;
            let lanes: Vec<Lane> = (0..n).map(|k| lane(&mut rng, k + batch)).collect();
            let mut kernel = ConductorLanes::new();
            for (k, (path, si, bsdf, u)) in lanes.iter().enumerate() {
                let Bxdf::Conductor(lobe) = bsdf.bxdf() else { panic!("lane {k} is not a conductor") };
                assert!(ConductorLanes::takes(lobe));
                kernel.take(k as u8, path, si, bsdf.frame(), lobe, u);
            }
            let (w, e) = scatter_and_check(&lanes, &mut kernel);
            (went_on, ended) = (went_on + w, ended + e);
        }
        // Most lanes go on, and some end (below the surface, or roulette).
        assert!(went_on > 5000 && ended > 200, "{went_on} went on, {ended} ended");
    }
}
