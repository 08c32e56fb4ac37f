//! The scatter stage across lanes, for diffuse vertices: the commonest
//! vertex of most scenes.
//!
//! The scatter stage of [`super::lanes`] gathers the lanes whose BSDF is a
//! plain diffuse lobe into structure of arrays (the shading normal and
//! ∂p/∂u, the direction the path came from, the albedo, the throughput,
//! the surface point with its error bounds and normal, and the vertex's
//! samples), and runs for all of them at once what the path integrator's
//! scalar scatter stage (`PathIntegrator::scatter`) runs for one:
//!
//! 0. the shading frame, by Gram–Schmidt (`Bsdf::new`'s, which the
//!    diffuse lanes' BSDFs skip: `Bsdf::diffuse_unframed`; one lane at a
//!    time its square root and division, waiting on each other, were
//!    about 3.5% of the Cornell box's time);
//! 1. the cosine-weighted direction of [`DiffuseBxdf::sample_f`]
//!    (Shirley and Chiu's concentric map of the square onto the disk,
//!    lifted onto the hemisphere by Malley's method; PBRT 4th ed.,
//!    §A.5.1 and §A.5.3) and its pdf, turned into world space by the
//!    shading frame;
//! 2. the throughput update `β ← β·f·|cos θ|/pdf`;
//! 3. the origin of the next ray, offset off the surface by its error
//!    bounds ([`crate::geometry::offset_ray_origin`], PBRT 4th ed.,
//!    §6.8.6);
//! 4. Russian roulette.
//!
//! Steps 2 to 4 are the same for every lobe: [`scatter_kernel`] runs a
//! lobe's samples ([`LobeLanes`]: this file's diffuse lobes, and the rough
//! conductors of [`super::conductor_lanes`]) and then [`continue_group`]
//! for each group of lanes, and [`ScatterSet`] holds the lanes, inputs and
//! outputs the kernels share.
//!
//! Each step is a loop over the lanes in scalar arithmetic, written
//! without branches so that the compiler turns it into vector
//! instructions, the cosine and sine of the disk's angle included
//! ([`crate::geometry::sin_cos_lane`], the same function the scalar
//! warps call). Every line is the `Vec3`/`Color` operation it replaces,
//! in the same order: each lane's new path state is the scalar stage's bit
//! for bit (a test compares them over random lanes; renders are
//! byte-identical).
//!
//! [`DiffuseBxdf::sample_f`]: crate::bsdf::DiffuseBxdf

use super::lanes::{LaneList, PathState};
use super::RR_DEPTH;
#[cfg(doc)]
use crate::bsdf::shading_frame;
use crate::bsdf::DiffuseBxdf;
use crate::geometry::isa;
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{coordinate_system_lane, group, set_group, sin_cos_lane, Frame, Ray, Vec3Lanes, GROUP, LANES};
use crate::integrator::RayStats;
use crate::interaction::SurfaceInteraction;
use crate::light::LightSampleContext;
use crate::sampling::VertexSamples;
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4};

/// The lanes taken by one of the scatter stage's kernels, what the kernel
/// needs of each lane's vertex, and what it finds: the part that the
/// diffuse and the conductor kernels share.
pub(super) struct ScatterSet {
    /// The lanes taken, in the order they were taken.
    pub(super) lanes: [u8; LANES],
    pub(super) len: usize,
    /// The kernel's inputs and outputs, kept from one stage to the next so
    /// that they are not cleared each time.
    pub(super) input: Inputs,
    pub(super) out: Outputs,
}

impl ScatterSet {
    /// No lanes.
    pub(super) const EMPTY: Self = Self { lanes: [0; LANES], len: 0, input: Inputs::ZERO, out: Outputs::ZERO };

    /// After the kernel ran: each lane's path gets its new throughput and
    /// ray, as the scalar `PathIntegrator::scatter` gives them, and the
    /// lanes whose paths go on are pushed to `next`.
    pub(super) fn continue_paths(
        &self,
        paths: &mut [PathState],
        hits: &[Option<SurfaceInteraction>],
        stats: &mut RayStats,
        next: &mut LaneList,
    ) {
        let out = &self.out;
        for (k, &lane) in self.lanes[..self.len].iter().enumerate() {
            if !out.sampled[k] {
                continue;
            }
            stats.secondary += 1;
            if !out.survives[k] {
                continue;
            }
            let i = lane as usize;
            let Some(si) = &hits[i] else { continue };
            let path = &mut paths[i];
            let wi = out.wi.get(k);
            path.beta = out.beta.get(k);
            path.specular_bounce = false;
            path.indirect = path.any_non_specular;
            path.any_non_specular = true;
            path.prev_pdf = out.pdf[k];
            path.prev_ctx = LightSampleContext { p: si.p, n: si.n };
            if si.media.is_transition() {
                path.medium = si.media.medium_along(wi, si.n);
            }
            path.ray = Ray::new(out.origin.get(k), wi);
            path.depth += 1;
            next.push(i);
        }
    }
}

/// The lanes of one scatter stage that a kernel takes: those whose BSDF is
/// one kind of lobe, `L`.
pub(super) struct ScatterLanes<L> {
    pub(super) set: ScatterSet,
    pub(super) lobes: L,
}

impl<L: LobeLanes> ScatterLanes<L> {
    /// Take `lane` (its path `path` at `si`, with the lobe `lobe` in the
    /// shading frame `frame`, and the vertex's samples `u`) as the kernel's
    /// next lane, writing what the kernel needs of it into its inputs while
    /// it is at hand.
    #[inline]
    pub(super) fn take(
        &mut self,
        lane: u8,
        path: &PathState,
        si: &SurfaceInteraction,
        frame: &Frame,
        lobe: &L::Bxdf,
        u: &VertexSamples,
    ) {
        let (k, input) = (self.set.len, &mut self.set.input);
        self.set.lanes[k] = lane;
        self.set.len += 1;
        input.fx.set(k, frame.x);
        input.fy.set(k, frame.y);
        input.fz.set(k, frame.z);
        input.wo.set(k, -path.ray.dir);
        input.beta.set(k, path.beta);
        input.p.set(k, si.p);
        input.p_error.set(k, si.p_error);
        input.n.set(k, si.n);
        (input.u[0][k], input.u[1][k]) = (u.dir.x, u.dir.y);
        input.u_rr[k] = u.rr;
        input.eta_scale[k] = path.eta_scale;
        input.roulette[k] = path.depth + 1 >= RR_DEPTH;
        self.lobes.set(k, lobe);
    }

    /// No lanes again, for the next stage.
    pub(super) fn clear(&mut self) {
        self.set.len = 0;
    }

    /// The scatter stage of the lanes taken: each lane's path gets its new
    /// throughput and ray, as the scalar `PathIntegrator::scatter` gives
    /// them, and the lanes whose paths go on are pushed to `next`.
    pub(super) fn scatter(
        &mut self,
        paths: &mut [PathState],
        hits: &[Option<SurfaceInteraction>],
        stats: &mut RayStats,
        next: &mut LaneList,
    ) {
        let set = &mut self.set;
        scatter_kernel(set.len, &set.input, &self.lobes, &mut set.out);
        set.continue_paths(paths, hits, stats, next);
    }
}

/// The diffuse lanes of one scatter stage.
pub(super) type DiffuseLanes = ScatterLanes<DiffuseLobes>;

/// The diffuse lobes of a kernel's lanes.
pub(super) struct DiffuseLobes {
    /// The diffuse albedo of each lane.
    albedo: Vec3Lanes,
}

impl DiffuseLanes {
    /// No lanes.
    pub(super) fn new() -> Self {
        Self { set: ScatterSet::EMPTY, lobes: DiffuseLobes { albedo: Vec3Lanes::ZERO } }
    }
}

/// What a scatter kernel needs of each lane.
pub(super) struct Inputs {
    /// The shading frame's axes (`fz`: the shading normal).
    pub(super) fx: Vec3Lanes,
    pub(super) fy: Vec3Lanes,
    pub(super) fz: Vec3Lanes,
    /// Towards where the path came from (unit).
    pub(super) wo: Vec3Lanes,
    /// The path throughput.
    pub(super) beta: Vec3Lanes,
    /// The surface point, its error bounds and its geometric normal.
    pub(super) p: Vec3Lanes,
    pub(super) p_error: Vec3Lanes,
    pub(super) n: Vec3Lanes,
    /// The direction's 2D sample and the roulette sample.
    pub(super) u: [[f32; LANES]; 2],
    pub(super) u_rr: [f32; LANES],
    /// The accumulated η² of refractions.
    pub(super) eta_scale: [f32; LANES],
    /// Whether Russian roulette plays at this vertex.
    pub(super) roulette: [bool; LANES],
}

impl Inputs {
    const ZERO: Self = Self {
        fx: Vec3Lanes::ZERO,
        fy: Vec3Lanes::ZERO,
        fz: Vec3Lanes::ZERO,
        wo: Vec3Lanes::ZERO,
        beta: Vec3Lanes::ZERO,
        p: Vec3Lanes::ZERO,
        p_error: Vec3Lanes::ZERO,
        n: Vec3Lanes::ZERO,
        u: [[0.0; LANES]; 2],
        u_rr: [0.0; LANES],
        eta_scale: [0.0; LANES],
        roulette: [false; LANES],
    };
}

/// What a scatter kernel finds for each lane.
pub(super) struct Outputs {
    /// Whether the BSDF gave a direction that carries light and a finite
    /// throughput: the path counts a secondary ray.
    pub(super) sampled: [bool; LANES],
    /// Whether the path goes on: sampled and not ended by roulette.
    pub(super) survives: [bool; LANES],
    /// The new direction (unit), its pdf, and the ray's origin off the
    /// surface.
    pub(super) wi: Vec3Lanes,
    pub(super) pdf: [f32; LANES],
    pub(super) origin: Vec3Lanes,
    /// The new throughput.
    pub(super) beta: Vec3Lanes,
    /// A radius and an angle of the direction's sample, and the angle's
    /// cosine and sine (between a kernel's loops).
    pub(super) radius: [f32; LANES],
    pub(super) theta: [f32; LANES],
    pub(super) cos: [f32; LANES],
    pub(super) sin: [f32; LANES],
}

impl Outputs {
    pub(super) const ZERO: Self = Self {
        sampled: [false; LANES],
        survives: [false; LANES],
        wi: Vec3Lanes::ZERO,
        pdf: [0.0; LANES],
        origin: Vec3Lanes::ZERO,
        beta: Vec3Lanes::ZERO,
        radius: [0.0; LANES],
        theta: [0.0; LANES],
        cos: [0.0; LANES],
        sin: [0.0; LANES],
    };
}

/// A lobe that a scatter kernel samples across lanes: its own inputs, lane
/// by lane, and how it samples them.
pub(super) trait LobeLanes {
    /// The BxDF whose lanes it takes.
    type Bxdf;
    /// Write what the kernel needs of `bxdf` into kernel lane `k`.
    fn set(&mut self, k: usize, bxdf: &Self::Bxdf);
    /// What the lobe computes one lane at a time for lanes `0..n` before
    /// the groups (into `out`'s scratch arrays): the C library's cosine and
    /// sine.
    fn prepare(&self, n: usize, input: &Inputs, out: &mut Outputs);
    /// The BSDF samples of the group of lanes `c..c + GROUP`, in world
    /// space.
    fn sample_group(&self, c: usize, input: &Inputs, out: &Outputs) -> GroupSample;
}

/// The scatter stage of lanes `0..n` with the lobes `lobes`, in the build
/// for this CPU.
pub(super) fn scatter_kernel<L: LobeLanes>(n: usize, input: &Inputs, lobes: &L, out: &mut Outputs) {
    match isa() {
        // SAFETY: `isa` found AVX2 (AVX-512 includes it).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 | Isa::Avx512 => unsafe { scatter_kernel_avx2(n, input, lobes, out) },
        _ => scatter_kernel_portable(n, input, lobes, out),
    }
}

/// [`scatter_kernel_portable`] compiled for AVX2: eight lanes to a
/// register.
///
/// # Safety
/// The CPU must have AVX2 and FMA. (FMA only makes the instructions
/// available: Rust never fuses a multiplication and an addition itself, so
/// the values are the portable build's.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn scatter_kernel_avx2<L: LobeLanes>(n: usize, input: &Inputs, lobes: &L, out: &mut Outputs) {
    scatter_kernel_portable(n, input, lobes, out);
}

/// The kernel: the scatter stage of lanes `0..n`. Its vector loops take
/// the lanes a [`GROUP`] at a time, each group's values in fixed-size
/// local arrays, so that every group is vector code (a loop over the count
/// would leave up to 31 lanes to a scalar remainder): the lobes' samples,
/// then [`continue_group`].
#[inline(always)]
pub(super) fn scatter_kernel_portable<L: LobeLanes>(n: usize, input: &Inputs, lobes: &L, out: &mut Outputs) {
    let n = n.min(LANES);
    lobes.prepare(n, input, out);
    for c in (0..n.div_ceil(GROUP)).map(|g| g * GROUP) {
        let s = lobes.sample_group(c, input, out);
        continue_group(c, input, &s, out);
    }
}

/// The next float up from `x` (`f32::next_up`), without branches.
#[inline(always)]
fn next_up(x: f32) -> f32 {
    step_away(x, false)
}

/// The next float down from `x` (`f32::next_down`), without branches.
#[inline(always)]
fn next_down(x: f32) -> f32 {
    step_away(x, true)
}

/// One step of the float grid from `x`: down if `down`, else up. Zeros step
/// to the smallest subnormal of the step's sign; NaN and the infinity
/// in the step's direction stay. (The bit-pattern rule of IEEE 754's
/// nextUp and nextDown, as `f32::next_up` and `f32::next_down` apply it.)
#[inline(always)]
fn step_away(x: f32, down: bool) -> f32 {
    let bits = x.to_bits();
    let abs = bits & 0x7fff_ffff;
    let negative = bits != abs;
    // Away from zero when the step goes the way of the sign, else towards.
    let away = negative == down;
    let stepped = if away { bits.wrapping_add(1) } else { bits.wrapping_sub(1) };
    let tiny = if down { 0x8000_0001 } else { 0x0000_0001 };
    let stepped = if abs == 0 { tiny } else { stepped };
    let inf = if down { f32::NEG_INFINITY } else { f32::INFINITY }.to_bits();
    let keep = x.is_nan() | (bits == inf);
    f32::from_bits(if keep { bits } else { stepped })
}

/// One group's BSDF samples, in world space: the direction `wi`, the
/// BSDF's value `f` and the pdf, and whether the lobe gave a sample at all
/// (`valid`).
pub(super) struct GroupSample {
    pub(super) wi: [[f32; GROUP]; 3],
    pub(super) f: [[f32; GROUP]; 3],
    pub(super) pdf: [f32; GROUP],
    pub(super) valid: [bool; GROUP],
}

impl GroupSample {
    /// No sample in any lane.
    pub(super) const ZERO: Self =
        Self { wi: [[0.0; GROUP]; 3], f: [[0.0; GROUP]; 3], pdf: [0.0; GROUP], valid: [false; GROUP] };
}

/// The rest of the scatter stage for the group of lanes `c..c + GROUP`,
/// once their lobe has sampled `s`: what `PathIntegrator::scatter` does
/// with a BSDF sample, operation for operation.
///
/// 1. the throughput update `β ← β·f·|cos θ|/pdf` (a sample that carries
///    no light or gives a throughput that is not finite ends the path);
/// 2. the origin of the next ray, offset off the surface by its error
///    bounds ([`crate::geometry::offset_ray_origin`], PBRT 4th ed.,
///    §6.8.6);
/// 3. Russian roulette.
#[inline(always)]
pub(super) fn continue_group(c: usize, input: &Inputs, s: &GroupSample, out: &mut Outputs) {
    let [fzx, fzy, fzz] = input.fz.group(c);
    let ([betax, betay, betaz], [px, py, pz]) = (input.beta.group(c), input.p.group(c));
    let ([errx, erry, errz], [nx, ny, nz]) = (input.p_error.group(c), input.n.group(c));
    let (eta, u_rr, roulette) = (group(&input.eta_scale, c), group(&input.u_rr, c), group(&input.roulette, c));
    let (mut sampled, mut survives) = ([false; GROUP], [false; GROUP]);
    let (mut origin, mut beta) = ([[0.0; GROUP]; 3], [[0.0; GROUP]; 3]);
    for j in 0..GROUP {
        let (wx, wy, wz) = (s.wi[0][j], s.wi[1][j], s.wi[2][j]);
        let (f_x, f_y, f_z) = (s.f[0][j], s.f[1][j], s.f[2][j]);
        let carries = (f_x > 0.0) | (f_y > 0.0) | (f_z > 0.0);
        let t = (wx * fzx[j] + wy * fzy[j] + wz * fzz[j]).abs() / s.pdf[j];
        let (bx, by, bz) = (betax[j] * (f_x * t), betay[j] * (f_y * t), betaz[j] * (f_z * t));
        let finite = bx.is_finite() & by.is_finite() & bz.is_finite();
        sampled[j] = s.valid[j] & carries & finite;
        // `offset_ray_origin`: off the surface by the error bounds along
        // the normal, on the side of `wi`, then one float further.
        let d = nx[j].abs() * errx[j] + ny[j].abs() * erry[j] + nz[j].abs() * errz[j];
        let (ex, ey, ez) = (d * nx[j], d * ny[j], d * nz[j]);
        let below = wx * nx[j] + wy * ny[j] + wz * nz[j] < 0.0;
        let (ex, ey, ez) = if below { (-ex, -ey, -ez) } else { (ex, ey, ez) };
        for (a, (po, e)) in [(px[j] + ex, ex), (py[j] + ey, ey), (pz[j] + ez, ez)].into_iter().enumerate() {
            let moved = if e > 0.0 { next_up(po) } else { next_down(po) };
            origin[a][j] = if (e == 0.0) | e.is_nan() { po } else { moved };
        }
        // Russian roulette: survive with probability min(max β·η², 0.95).
        let survive = (bx * eta[j]).max(by * eta[j]).max(bz * eta[j]).min(0.95);
        let lost = roulette[j] & (u_rr[j] >= survive);
        let (bx, by, bz) = if roulette[j] { (bx / survive, by / survive, bz / survive) } else { (bx, by, bz) };
        survives[j] = sampled[j] & !lost;
        (beta[0][j], beta[1][j], beta[2][j]) = (bx, by, bz);
    }
    set_group(&mut out.sampled, c, sampled);
    set_group(&mut out.survives, c, survives);
    set_group(&mut out.pdf, c, s.pdf);
    out.wi.set_group(c, s.wi);
    out.origin.set_group(c, origin);
    out.beta.set_group(c, beta);
}

impl LobeLanes for DiffuseLobes {
    type Bxdf = DiffuseBxdf;

    #[inline(always)]
    fn set(&mut self, k: usize, diffuse: &DiffuseBxdf) {
        self.albedo.set(k, diffuse.r);
    }

    /// Shirley and Chiu's concentric map (`sampling::concentric_disk`):
    /// the radius and angle of the disk point, then the angle's sine and
    /// cosine ([`sin_cos_lane`]: the angle is within `[−π/4, 3π/4]`).
    #[inline(always)]
    fn prepare(&self, n: usize, input: &Inputs, out: &mut Outputs) {
        // (A loop over the lanes, not over groups: the loop vectoriser
        // takes it, where it would leave the unrolled groups to scalar code
        // with a branch for the quotient. The count rounded up to whole
        // groups.)
        let whole = (n.div_ceil(GROUP) * GROUP).min(LANES);
        for k in 0..whole {
            let (ox, oy) = (2.0 * input.u[0][k] - 1.0, 2.0 * input.u[1][k] - 1.0);
            let wide = ox.abs() > oy.abs();
            // One quotient, of the operands the lane needs, for either
            // branch of the map (`oy/ox` or `ox/oy`).
            let (num, den) = if wide { (oy, ox) } else { (ox, oy) };
            let q = num / den;
            out.radius[k] = den;
            out.theta[k] = if wide { FRAC_PI_4 * q } else { 2.0 * FRAC_PI_4 - FRAC_PI_4 * q };
        }
        for k in 0..whole {
            (out.sin[k], out.cos[k]) = sin_cos_lane(out.theta[k]);
        }
    }

    /// `DiffuseBxdf::sample_f` of each lane of the group, and its value
    /// `R/π`. The lanes' frames come unfinished (`Bsdf::diffuse_unframed`:
    /// `fx` holds ∂p/∂u, `fz` the shading normal) and are made here first,
    /// with [`shading_frame`]'s operations.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn sample_group(&self, c: usize, input: &Inputs, out: &Outputs) -> GroupSample {
        let (u0, u1) = (group(&input.u[0], c), group(&input.u[1], c));
        let (radius, cos, sin) = (group(&out.radius, c), group(&out.cos, c), group(&out.sin, c));
        let ([fxx, fxy, fxz], [fyx, fyy, fyz]) = shading_frames(input.fx.group(c), input.fz.group(c));
        let [fzx, fzy, fzz] = input.fz.group(c);
        let ([wox, woy, woz], [rx, ry, rz]) = (input.wo.group(c), self.albedo.group(c));
        let mut s = GroupSample::ZERO;
        for j in 0..GROUP {
            // `concentric_disk`: the centre of the square maps to the
            // centre.
            let (ox, oy) = (2.0 * u0[j] - 1.0, 2.0 * u1[j] - 1.0);
            let centre = (ox == 0.0) & (oy == 0.0);
            let (dx, dy) = (radius[j] * cos[j], radius[j] * sin[j]);
            let (dx, dy) = if centre { (0.0, 0.0) } else { (dx, dy) };
            // `cosine_hemisphere`, then `DiffuseBxdf::sample_f` on the side
            // of `wo` (the local z of `wo` is its dot product with the
            // normal).
            let z = (1.0 - dx * dx - dy * dy).max(0.0).sqrt();
            let wo_z = wox[j] * fzx[j] + woy[j] * fzy[j] + woz[j] * fzz[j];
            let z = if wo_z < 0.0 { -z } else { z };
            let pdf = z.abs() * FRAC_1_PI;
            s.pdf[j] = pdf;
            s.valid[j] = (wo_z != 0.0) & (pdf > 0.0) & (z != 0.0);
            // `Frame::from_local`.
            s.wi[0][j] = fxx[j] * dx + fyx[j] * dy + fzx[j] * z;
            s.wi[1][j] = fxy[j] * dx + fyy[j] * dy + fzy[j] * z;
            s.wi[2][j] = fxz[j] * dx + fyz[j] * dy + fzz[j] * z;
            // f = R/π.
            (s.f[0][j], s.f[1][j], s.f[2][j]) = (rx[j] * FRAC_1_PI, ry[j] * FRAC_1_PI, rz[j] * FRAC_1_PI);
        }
        s
    }
}

/// The tangents `x` and `y` of [`shading_frame`]`(ns, dpdu)` for a group
/// of lanes: `dpdu` made orthogonal to the unit normal `ns` and
/// normalised, and `ns × x`; where `dpdu` is not finite, zero or (nearly)
/// parallel to `ns`, those of `Frame::from_z(ns)` (`coordinate_system`).
/// Each line is the `Vec3` operation it replaces, in the same order (the
/// dot products `(x + y) + z`), so each lane's frame is the scalar one bit
/// for bit.
#[inline(always)]
fn shading_frames(dpdu: [[f32; GROUP]; 3], ns: [[f32; GROUP]; 3]) -> ([[f32; GROUP]; 3], [[f32; GROUP]; 3]) {
    let ([tx, ty, tz], [nx, ny, nz]) = (dpdu, ns);
    let (mut x, mut y) = ([[0.0; GROUP]; 3], [[0.0; GROUP]; 3]);
    for j in 0..GROUP {
        // Gram–Schmidt: `dpdu − ns (ns · dpdu)`, normalised.
        let d = nx[j] * tx[j] + ny[j] * ty[j] + nz[j] * tz[j];
        let (gx, gy, gz) = (tx[j] - nx[j] * d, ty[j] - ny[j] * d, tz[j] - nz[j] * d);
        let len2 = gx * gx + gy * gy + gz * gz;
        let dpdu2 = tx[j] * tx[j] + ty[j] * ty[j] + tz[j] * tz[j];
        let usable = !(!len2.is_finite() | (len2 <= 1e-12 * dpdu2));
        let len = len2.sqrt();
        let (gx, gy, gz) = (gx / len, gy / len, gz / len);
        // `ns × x`.
        let (hx, hy, hz) = (ny[j] * gz - nz[j] * gy, nz[j] * gx - nx[j] * gz, nx[j] * gy - ny[j] * gx);
        // `Frame::from_z(ns)`.
        let ([cx, cy, cz], [ex, ey, ez]) = coordinate_system_lane([nx[j], ny[j], nz[j]]);
        (x[0][j], x[1][j], x[2][j]) = if usable { (gx, gy, gz) } else { (cx, cy, cz) };
        (y[0][j], y[1][j], y[2][j]) = if usable { (hx, hy, hz) } else { (ex, ey, ez) };
    }
    (x, y)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, Bxdf};
    use crate::color::Color;
    use crate::geometry::{Vec2, Vec3};
    use crate::integrator::path::PathIntegrator;
    use crate::material::MaterialId;
    use crate::medium::MediumInterface;
    use crate::mesh::VertexAttributes;
    use crate::sampling::Pcg32;

    /// The branch-free float steps are `f32::next_up` and `f32::next_down`
    /// on every kind of float.
    #[test]
    fn float_steps_equal_the_standard_ones() {
        let mut rng = Pcg32::new(3, 9);
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x8000_0001),
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let random = (0..10_000).map(|_| f32::from_bits(rng.next_u32()));
        for x in special.into_iter().chain(random) {
            assert_eq!(next_up(x).to_bits(), x.next_up().to_bits(), "next_up({x:e})");
            assert_eq!(next_down(x).to_bits(), x.next_down().to_bits(), "next_down({x:e})");
        }
    }

    /// A lane of a kernel test: the path, its hit, the BSDF there and the
    /// vertex's samples.
    pub(in crate::integrator::path) type Lane = (PathState, SurfaceInteraction, Bsdf, VertexSamples);

    /// A random path (throughputs small and large, depths before and past
    /// the roulette's) at a random hit, for the scatter kernels' tests.
    pub(in crate::integrator::path) fn random_vertex(rng: &mut Pcg32, k: usize) -> (PathState, SurfaceInteraction) {
        let mut v = || Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        let (origin, dir, p, n, ns, dpdu) = (v(), v(), v() * 10.0, v().normalize(), v().normalize(), v());
        let p_error = v().abs() * 1e-5;
        let mut path = PathState::new(&Ray::new(origin, dir), None);
        path.beta = Color::new(rng.uniform(), rng.uniform(), rng.uniform()) * [0.01, 1.0, 30.0][k % 3];
        path.eta_scale = [1.0, 2.25, 0.44][k % 3];
        path.depth = k as u32 % 8;
        path.any_non_specular = k.is_multiple_of(2);
        let si = SurfaceInteraction {
            t: 1.0,
            p,
            p_error,
            n,
            ns,
            uv: Vec2::ZERO,
            attributes: VertexAttributes::default(),
            dpdu,
            dpdv: n.cross(dpdu),
            material: MaterialId::new(0),
            light: None,
            media: MediumInterface::default(),
        };
        (path, si)
    }

    /// Run `kernel`, which has taken `lanes` in order, in its portable
    /// build and in the build for this CPU, and check that both agree and
    /// that each lane's path state is the scalar scatter stage's bit for
    /// bit (whether it goes on, the count of secondary rays, the
    /// throughput, the ray, the pdf and the flags). Returns how many lanes
    /// went on and how many ended.
    pub(in crate::integrator::path) fn scatter_and_check<L: LobeLanes>(
        lanes: &[Lane],
        kernel: &mut ScatterLanes<L>,
    ) -> (usize, usize) {
        let n = lanes.len();
        let mut paths: Vec<PathState> = lanes.iter().map(|l| l.0).collect();
        let hits: Vec<Option<SurfaceInteraction>> = lanes.iter().map(|l| Some(l.1)).collect();
        let mut portable = Outputs::ZERO;
        scatter_kernel_portable(n, &kernel.set.input, &kernel.lobes, &mut portable);
        let (mut stats, mut next) = (RayStats::default(), LaneList::empty());
        kernel.scatter(&mut paths, &hits, &mut stats, &mut next);
        let out = &kernel.set.out;
        for k in 0..n {
            assert_eq!((portable.sampled[k], portable.survives[k]), (out.sampled[k], out.survives[k]));
            if out.survives[k] {
                let of = |o: &Outputs| (o.wi.get(k), o.origin.get(k), o.beta.get(k), o.pdf[k]);
                assert_eq!(of(&portable), of(out), "lane {k} of {n}");
            }
        }
        let integrator = PathIntegrator::new(100);
        let (mut went_on, mut ended) = (0, 0);
        let mut scalar_stats = RayStats::default();
        for (k, (path, si, bsdf, u)) in lanes.iter().enumerate() {
            let mut scalar = *path;
            let goes_on = integrator.scatter(&mut scalar, si, bsdf, u, &mut scalar_stats);
            assert_eq!(goes_on, next.as_slice().contains(&(k as u8)), "lane {k} of {n}: {bsdf:?} {u:?}");
            if !goes_on {
                ended += 1;
                continue;
            }
            went_on += 1;
            let lane = &paths[k];
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(lane.beta), bits(scalar.beta), "throughput of lane {k} of {n}: {bsdf:?}");
            assert_eq!(bits(lane.ray.origin), bits(scalar.ray.origin), "origin of lane {k} of {n}");
            assert_eq!(bits(lane.ray.dir), bits(scalar.ray.dir), "direction of lane {k} of {n}");
            assert_eq!(lane.prev_pdf.to_bits(), scalar.prev_pdf.to_bits(), "pdf of lane {k} of {n}");
            assert_eq!((lane.prev_ctx.p, lane.prev_ctx.n), (scalar.prev_ctx.p, scalar.prev_ctx.n));
            assert_eq!((lane.depth, lane.eta_scale.to_bits()), (scalar.depth, scalar.eta_scale.to_bits()));
            assert_eq!(
                (lane.specular_bounce, lane.indirect, lane.any_non_specular),
                (scalar.specular_bounce, scalar.indirect, scalar.any_non_specular)
            );
        }
        assert_eq!(stats.secondary, scalar_stats.secondary, "secondary rays");
        (went_on, ended)
    }

    /// A random lane with a diffuse BSDF, with the corner cases of the
    /// concentric map and of the throughput mixed in.
    fn lane(rng: &mut Pcg32, k: usize) -> Lane {
        let (mut path, mut si) = random_vertex(rng, k);
        // Tangents that `shading_frame` rejects for `Frame::from_z`'s:
        // zero, parallel to the normal (and nearly), not finite.
        match k % 19 {
            0 => si.dpdu = Vec3::ZERO,
            1 => si.dpdu = si.ns * 3.0,
            2 => si.dpdu = si.ns * 0.5 + Vec3::splat(1e-7),
            3 => si.dpdu = Vec3::new(f32::INFINITY, 1.0, 0.0),
            4 => si.dpdu = Vec3::new(f32::NAN, 1.0, 0.0),
            5 => si.dpdu = si.ns * 1e30,
            _ => {}
        }
        let (ns, dpdu) = (si.ns, si.dpdu);
        let mut r = Color::new(rng.uniform(), rng.uniform(), rng.uniform());
        if k.is_multiple_of(11) {
            r = Color::ZERO;
        }
        let bsdf = Bsdf::new(ns, dpdu, Bxdf::Diffuse(DiffuseBxdf { r }));
        let mut dir_u = Vec2::new(rng.uniform(), rng.uniform());
        match k % 13 {
            // The centre of the square, and points on its diagonals and
            // axes.
            0 => dir_u = Vec2::splat(0.5),
            1 => dir_u = Vec2::new(dir_u.x, dir_u.x),
            2 => dir_u = Vec2::new(dir_u.x, 1.0 - dir_u.x),
            3 => dir_u = Vec2::new(0.5, dir_u.y),
            4 => dir_u = Vec2::new(dir_u.x, 0.5),
            5 => dir_u = Vec2::ZERO,
            _ => {}
        }
        if k.is_multiple_of(17) {
            // `wo` in the shading plane.
            path.ray.dir = bsdf.frame().x;
        }
        let u = VertexSamples { light: 0.0, point: Vec2::ZERO, lobe: rng.uniform(), dir: dir_u, rr: rng.uniform() };
        (path, si, bsdf, u)
    }

    /// The kernel gives each lane the path state that the scalar scatter
    /// stage gives it, bit for bit, over random lanes in batches of 1 to 64,
    /// with roulette and without; and the portable build equals the build
    /// for this CPU ([`scatter_and_check`]). The kernel takes each lane's
    /// BSDF with its frame unfinished, as the path integrator gives it
    /// (`Bsdf::diffuse_unframed`), and makes the frame that the scalar
    /// stage's `Bsdf::new` made, unusable tangents included.
    #[test]
    fn diffuse_lanes_equal_the_scalar_scatter() {
        let mut rng = Pcg32::new(11, 5);
        let mut went_on = 0;
        for batch in 0..300 {
            let n = 1 + batch % LANES;
            let lanes: Vec<Lane> = (0..n).map(|k| lane(&mut rng, k + batch)).collect();
            let mut kernel = DiffuseLanes::new();
            for (k, (path, si, bsdf, u)) in lanes.iter().enumerate() {
                let Bxdf::Diffuse(lobe) = bsdf.bxdf() else { panic!("lane {k} is not diffuse") };
                let unframed = Bsdf::diffuse_unframed(si.ns, si.dpdu, *lobe);
                assert!(unframed.frame_pending() && !bsdf.frame_pending());
                kernel.take(k as u8, path, si, unframed.frame(), lobe, u);
            }
            went_on += scatter_and_check(&lanes, &mut kernel).0;
        }
        // Most lanes go on.
        assert!(went_on > 4000, "{went_on}");
    }
}
