//! The Trowbridge–Reitz (GGX) microfacet distribution, isotropic, with
//! Smith's masking-shadowing and sampling of visible normals.
//!
//! Sources: Trowbridge & Reitz, JOSA 65(5), 1975; Walter et al.,
//! "Microfacet Models for Refraction through Rough Surfaces", EGSR 2007;
//! Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs", JCGT 3(2), 2014; Heitz, "Sampling the GGX Distribution of
//! Visible Normals", JCGT 7(4), 2018; PBRT 4th ed., §9.6.
//!
//! All directions are in the local frame (macro normal `+z`); microfacet
//! normals `wm` are on the upper side.

use crate::geometry::{Vec2, Vec3};
use std::f32::consts::PI;

/// Below this α a surface is treated as perfectly smooth (a delta lobe), as
/// PBRT-v4's `EffectivelySmooth`: such a lobe is too narrow for f32.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// Isotropic Trowbridge–Reitz (GGX) distribution of microfacet normals with
/// roughness `α` (the slope scale; `α = roughness` in the scene files).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha: f32,
}

impl TrowbridgeReitz {
    /// The distribution with roughness `alpha` (negative or NaN values are
    /// taken as 0).
    pub fn new(alpha: f32) -> Self {
        Self { alpha: if alpha > 0.0 { alpha } else { 0.0 } }
    }

    /// Roughness α.
    #[inline]
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// Whether the surface is, for f32 purposes, a perfect mirror or
    /// refractor: `α < 1e-3`.
    #[inline]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha < SMOOTH_ALPHA
    }

    /// Density of microfacet normals per unit projected area,
    /// `D(wm) = 1 / (π α² cos⁴θm (1 + tan²θm/α²)²)`, normalised so that
    /// `∫ D(wm) cos θm dωm = 1`. Written as
    /// `1 / (π α² (sin²θm/α² + cos²θm)²)`, which has no tangent to
    /// overflow. Zero on the lower hemisphere.
    #[inline]
    pub fn d(&self, wm: Vec3) -> f32 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = (wm.x * wm.x + wm.y * wm.y) / a2 + wm.z * wm.z;
        1.0 / (PI * a2 * t * t)
    }

    /// Smith's auxiliary function for GGX,
    /// `Λ(w) = (√(1 + α² tan²θ) − 1) / 2` (Heitz 2014, eq. 72). Infinite at
    /// grazing.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (w.x * w.x + w.y * w.y) / z2;
        let a2 = self.alpha * self.alpha;
        0.5 * ((1.0 + a2 * tan2).sqrt() - 1.0)
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
    /// from `−w` (for an isotropic distribution the same as seen from `w`
    /// mirrored in the surface).
    ///
    /// The method: stretch `w` by α to the configuration where the
    /// distribution is the unit hemisphere (α = 1); there the visible
    /// normals are uniform on the projected disk, which is a half disk
    /// (towards `w`) joined with half an ellipse of axis ratio `cos θ`;
    /// sample the disk, squash the far half, lift to the hemisphere, and
    /// unstretch the normal.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        let mut wh = Vec3::new(self.alpha * w.x, self.alpha * w.y, w.z).normalize_or(Vec3::Z);
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
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        // Squash the half facing away from wh onto the projected ellipse.
        let s = 0.5 * (1.0 + wh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        // Lift to the hemisphere around wh, then unstretch.
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * wh;
        Vec3::new(self.alpha * nh.x, self.alpha * nh.y, nh.z.max(1e-6)).normalize()
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
}
