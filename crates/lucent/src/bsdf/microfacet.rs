//! The Trowbridge–Reitz (GGX) microfacet distribution, anisotropic, with
//! Smith's masking-shadowing and sampling of visible normals.
//!
//! Sources: Trowbridge & Reitz, JOSA 65(5), 1975; Walter et al.,
//! "Microfacet Models for Refraction through Rough Surfaces", EGSR 2007;
//! Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs", JCGT 3(2), 2014; Heitz, "Sampling the GGX Distribution of
//! Visible Normals", JCGT 7(4), 2018; PBRT 4th ed., §9.6.
//!
//! All directions are in the local frame (macro normal `+z`, `x` along the
//! surface's ∂p/∂u); microfacet normals `wm` are on the upper side. The
//! roughness along `x` is `αx`, along `y` is `αy`.

use crate::geometry::{sin_cos, Vec2, Vec3};
use std::f32::consts::PI;

/// Below this α a surface is treated as perfectly smooth (a delta lobe), as
/// PBRT-v4's `EffectivelySmooth`: such a lobe is too narrow for f32.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// pbrt-v4's map from a scene file's `roughness` to the GGX `α` when
/// `remaproughness` is true (its default): `α = √roughness`
/// (`TrowbridgeReitzDistribution::RoughnessToAlpha`, PBRT 4th ed., §9.6.1).
/// Negative or NaN input gives 0.
#[inline]
pub fn roughness_to_alpha(roughness: f32) -> f32 {
    if roughness > 0.0 {
        roughness.sqrt()
    } else {
        0.0
    }
}

/// Anisotropic Trowbridge–Reitz (GGX) distribution of microfacet normals
/// with roughness `αx` along the local `x` axis and `αy` along `y` (the
/// slope scales; `α = roughness` in lucent's own scene files, `√roughness`
/// in pbrt-v4's, see [`roughness_to_alpha`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha_x: f32,
    alpha_y: f32,
}

impl TrowbridgeReitz {
    /// The isotropic distribution with roughness `alpha` (negative or NaN
    /// values are taken as 0).
    pub fn new(alpha: f32) -> Self {
        Self::anisotropic(alpha, alpha)
    }

    /// The anisotropic distribution with roughness `alpha_x` along the
    /// local `x` axis (∂p/∂u) and `alpha_y` along `y` (negative or NaN
    /// values are taken as 0). Unless both are below [`SMOOTH_ALPHA`], each
    /// is raised to at least 1e-4, as in PBRT-v4: a distribution smooth in
    /// one direction only would divide by zero in `D`.
    pub fn anisotropic(alpha_x: f32, alpha_y: f32) -> Self {
        let clean = |a: f32| {
            if a > 0.0 && a.is_finite() {
                a
            } else if a == f32::INFINITY {
                1e4
            } else {
                0.0
            }
        };
        let (mut ax, mut ay) = (clean(alpha_x), clean(alpha_y));
        if ax.max(ay) >= SMOOTH_ALPHA {
            ax = ax.max(1e-4);
            ay = ay.max(1e-4);
        }
        Self { alpha_x: ax, alpha_y: ay }
    }

    /// Roughness αx along the local `x` axis.
    #[inline]
    pub fn alpha_x(&self) -> f32 {
        self.alpha_x
    }

    /// Roughness αy along the local `y` axis.
    #[inline]
    pub fn alpha_y(&self) -> f32 {
        self.alpha_y
    }

    /// Roughness α of an isotropic distribution; for an anisotropic one,
    /// the geometric mean `√(αx αy)`.
    #[inline]
    pub fn alpha(&self) -> f32 {
        if self.alpha_x == self.alpha_y {
            self.alpha_x
        } else {
            (self.alpha_x * self.alpha_y).sqrt()
        }
    }

    /// Whether the surface is, for f32 purposes, a perfect mirror or
    /// refractor: `max(αx, αy) < 1e-3`.
    #[inline]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < SMOOTH_ALPHA
    }

    /// PBRT-v4's path regularisation (§14.1.6 of the online edition,
    /// `TrowbridgeReitzDistribution::Regularize`): each `α < 0.3` becomes
    /// `clamp(2α, 0.1, 0.3)`, so near-specular lobes seen after a diffuse
    /// bounce are widened and caustic paths become less noisy (biased).
    pub fn regularize(&mut self) {
        let widen = |a: f32| if a < 0.3 { (2.0 * a).clamp(0.1, 0.3) } else { a };
        self.alpha_x = widen(self.alpha_x);
        self.alpha_y = widen(self.alpha_y);
    }

    /// Density of microfacet normals per unit projected area,
    /// `D(wm) = 1 / (π αx αy cos⁴θm (1 + tan²θm (cos²φm/αx² + sin²φm/αy²))²)`,
    /// normalised so that `∫ D(wm) cos θm dωm = 1` (PBRT 4th ed., eq. 9.16).
    /// Written as `1 / (π αx αy (x²/αx² + y²/αy² + z²)²)`, which has no
    /// tangent to overflow. Zero on the lower hemisphere.
    #[inline]
    pub fn d(&self, wm: Vec3) -> f32 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let (sx, sy) = (wm.x / self.alpha_x, wm.y / self.alpha_y);
        let t = sx * sx + sy * sy + wm.z * wm.z;
        1.0 / (PI * self.alpha_x * self.alpha_y * t * t)
    }

    /// Smith's auxiliary function for GGX,
    /// `Λ(w) = (√(1 + α(φ)² tan²θ) − 1) / 2` with
    /// `α(φ)² = αx² cos²φ + αy² sin²φ` (Heitz 2014, eq. 72 and 80; PBRT 4th
    /// ed., eq. 9.20). Infinite at grazing.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let (ax, ay) = (w.x * self.alpha_x, w.y * self.alpha_y);
        let a2_tan2 = (ax * ax + ay * ay) / z2;
        0.5 * ((1.0 + a2_tan2).sqrt() - 1.0)
    }

    /// Smith masking `G1(w) = 1 / (1 + Λ(w))`.
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing
    /// `G(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi))` (Heitz 2014, eq. 99).
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Distribution of normals visible from `w`,
    /// `D_w(wm) = G1(w)/cos θ · D(wm) · max(0, w·wm)` (Heitz 2014, eq. 16):
    /// the solid-angle density of [`TrowbridgeReitz::sample_wm`]. For `w`
    /// below the surface, the normals visible from `−w` (as `sample_wm`).
    /// Zero at grazing `w`.
    #[inline]
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        if w.z == 0.0 {
            return 0.0;
        }
        let w = if w.z < 0.0 { -w } else { w };
        let cos_m = w.dot(wm);
        if cos_m <= 0.0 {
            return 0.0;
        }
        self.g1(w) / w.z * self.d(wm) * cos_m
    }

    /// Sample a microfacet normal visible from `w` with density
    /// [`TrowbridgeReitz::d_visible`] (Heitz 2018). A `w` below the surface
    /// is mirrored through the origin first, so the normals are those seen
    /// from `−w` (the same as seen from `w` mirrored in the surface: `D` is
    /// even in `x` and in `y`).
    ///
    /// The method: stretch `w` by (αx, αy) to the configuration where the
    /// distribution is the unit hemisphere (α = 1); there the visible
    /// normals are uniform on the projected disk, which is a half disk
    /// (towards `w`) joined with half an ellipse of axis ratio `cos θ`;
    /// sample the disk, squash the far half, lift to the hemisphere, and
    /// unstretch the normal.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize_or(Vec3::Z);
        if wh.z < 0.0 {
            wh = -wh;
        }
        // A frame around wh with t1 horizontal.
        let len2 = wh.x * wh.x + wh.y * wh.y;
        let t1 = if len2 > 0.0 { Vec3::new(-wh.y, wh.x, 0.0) / len2.sqrt() } else { Vec3::X };
        let t2 = wh.cross(t1);
        // Uniform point on the unit disk (polar map, as in the paper).
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let (sin_phi, cos_phi) = sin_cos(phi);
        let p1 = r * cos_phi;
        let mut p2 = r * sin_phi;
        // Squash the half facing away from wh onto the projected ellipse.
        let s = 0.5 * (1.0 + wh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        // Lift to the hemisphere around wh, then unstretch.
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * wh;
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ over the sphere of g(ω) dω by the midpoint rule in (cos θ, φ),
    /// with extra resolution near the pole where sharp lobes live.
    fn integrate_sphere(mut g: impl FnMut(Vec3) -> f64) -> f64 {
        // Substitute cos θ = 1 − 2 t², concentrating points near the pole.
        let (nt, np) = (2000, 200);
        let mut sum = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) / nt as f64;
            let c = 1.0 - 2.0 * t * t;
            let dc = 4.0 * t / nt as f64;
            let s = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..np {
                let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                let w = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                sum += g(w) * dc * 2.0 * std::f64::consts::PI / np as f64;
            }
        }
        sum
    }

    #[test]
    fn projected_area_of_normals_is_one() {
        for alpha in [0.1f32, 0.3, 0.8, 1.0] {
            let m = TrowbridgeReitz::new(alpha);
            let v = integrate_sphere(|w| (m.d(w) * w.z) as f64);
            assert!((v - 1.0).abs() < 5e-3, "α {alpha}: {v}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        for alpha in [0.1f32, 0.5, 1.0] {
            let m = TrowbridgeReitz::new(alpha);
            for wo in [Vec3::Z, Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.0, 0.995, 0.0999).normalize()] {
                let v = integrate_sphere(|w| m.d_visible(wo, w) as f64);
                assert!((v - 1.0).abs() < 5e-3, "α {alpha} wo {wo}: {v}");
            }
        }
    }

    #[test]
    fn masking_limits() {
        let m = TrowbridgeReitz::new(0.5);
        assert_eq!(m.g1(Vec3::Z), 1.0);
        assert_eq!(m.g1(Vec3::X), 0.0);
        let w = Vec3::new(0.6, 0.0, 0.8);
        assert!((m.g(w, Vec3::Z) - m.g1(w)).abs() < 1e-7);
        // Height-correlated G lies between the uncorrelated product and
        // the smaller G1.
        let wi = Vec3::new(-0.3, 0.5, 0.812).normalize();
        let g = m.g(w, wi);
        assert!(g >= m.g1(w) * m.g1(wi) - 1e-7 && g <= m.g1(w).min(m.g1(wi)) + 1e-7);
    }

    #[test]
    fn sampled_normals_are_visible_and_upper() {
        let m = TrowbridgeReitz::new(0.4);
        let mut rng = crate::sampling::Pcg32::new(5, 1);
        for wo in [Vec3::Z, Vec3::new(0.99, 0.0, 0.141).normalize(), Vec3::new(0.3, 0.4, -0.866).normalize()] {
            for _ in 0..10_000 {
                let wm = m.sample_wm(wo, Vec2::new(rng.uniform(), rng.uniform()));
                assert!(wm.is_finite() && wm.z > 0.0 && (wm.length() - 1.0).abs() < 1e-4);
                assert!(wo.dot(wm) * wo.z.signum() >= -1e-5);
            }
        }
    }

    #[test]
    fn anisotropic_distribution_is_normalised() {
        for (ax, ay) in [(0.1f32, 0.4f32), (0.5, 0.05), (0.8, 0.3)] {
            let m = TrowbridgeReitz::anisotropic(ax, ay);
            let v = integrate_sphere(|w| (m.d(w) * w.z) as f64);
            assert!((v - 1.0).abs() < 5e-3, "α ({ax}, {ay}): {v}");
            for wo in [Vec3::Z, Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.3, -0.9, 0.316).normalize()] {
                let v = integrate_sphere(|w| m.d_visible(wo, w) as f64);
                assert!((v - 1.0).abs() < 5e-3, "α ({ax}, {ay}) wo {wo}: {v}");
            }
        }
    }

    #[test]
    fn anisotropic_lambda_uses_the_azimuthal_roughness() {
        // Along x the distribution behaves as an isotropic one of αx, along
        // y as one of αy (Heitz 2014, eq. 80).
        let m = TrowbridgeReitz::anisotropic(0.2, 0.7);
        let w = Vec3::new(0.6, 0.0, 0.8);
        assert!((m.lambda(w) - TrowbridgeReitz::new(0.2).lambda(w)).abs() < 1e-6);
        let w = Vec3::new(0.0, 0.6, 0.8);
        assert!((m.lambda(w) - TrowbridgeReitz::new(0.7).lambda(w)).abs() < 1e-6);
        // D at the pole is 1/(π αx αy).
        assert!((m.d(Vec3::Z) - 1.0 / (PI * 0.2 * 0.7)).abs() < 1e-4);
    }

    #[test]
    fn remap_and_regularize_follow_pbrt() {
        assert_eq!(roughness_to_alpha(0.25), 0.5);
        assert_eq!(roughness_to_alpha(-1.0), 0.0);
        let mut m = TrowbridgeReitz::anisotropic(0.0, 0.0);
        assert!(m.effectively_smooth());
        m.regularize();
        assert_eq!((m.alpha_x(), m.alpha_y()), (0.1, 0.1));
        let mut m = TrowbridgeReitz::anisotropic(0.12, 0.5);
        m.regularize();
        assert_eq!((m.alpha_x(), m.alpha_y()), (0.24, 0.5));
        // Rough in one direction only: the other is raised to 1e-4.
        let m = TrowbridgeReitz::anisotropic(0.3, 0.0);
        assert_eq!(m.alpha_y(), 1e-4);
    }
}
