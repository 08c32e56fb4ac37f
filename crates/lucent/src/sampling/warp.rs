use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4};

/// Map the unit square to the unit disk uniformly by area, keeping strata
/// contiguous (Shirley & Chiu, "A Low Distortion Map Between Disk and
/// Square", JGT 2(3), 1997). `(0.5, 0.5)` maps to the centre.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine-weighted direction on the upper (`z ≥ 0`) unit hemisphere, by
/// Malley's method: a uniform point on the disk lifted onto the hemisphere
/// (PBRT 4th ed., §A.5.3). The density is [`cosine_hemisphere_pdf`].
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Solid-angle density of [`cosine_hemisphere`]: `cos θ / π`.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta * FRAC_1_PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_into_the_disk_and_covers_it_uniformly() {
        // Equal-area check: the fraction of a fine grid landing within
        // radius 0.5 must be 1/4.
        let n = 400;
        let mut inner = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = concentric_disk(u);
                assert!(d.length() <= 1.0 + 1e-6);
                if d.length() < 0.5 {
                    inner += 1;
                }
            }
        }
        let frac = inner as f32 / (n * n) as f32;
        assert!((frac - 0.25).abs() < 0.01, "{frac}");
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
    }

    #[test]
    fn cosine_hemisphere_is_unit_upper_and_has_mean_cosine_two_thirds() {
        // E[cos θ] under the density cos θ / π is 2/3.
        let n = 200;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let w = cosine_hemisphere(Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                assert!((w.length() - 1.0).abs() < 1e-5 && w.z >= 0.0);
                sum += w.z as f64;
            }
        }
        let mean = sum / (n * n) as f64;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "{mean}");
        assert_eq!(cosine_hemisphere(Vec2::splat(0.5)), Vec3::Z);
        assert!((cosine_hemisphere_pdf(1.0) - FRAC_1_PI).abs() < 1e-7);
    }
}
