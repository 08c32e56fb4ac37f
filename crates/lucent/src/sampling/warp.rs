use glam::Vec2;
use std::f32::consts::FRAC_PI_4;

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
}
