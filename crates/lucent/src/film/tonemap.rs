use crate::color::{luminance, Color};

/// How radiance values above 1 are brought into the displayable range
/// before quantising.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ToneMap {
    /// The classic ray tracer's rule: when the largest channel exceeds 1,
    /// divide all three by it. Keeps the hue; values ≤ 1 are untouched.
    #[default]
    Classic,
    /// Clamp each channel to `[0, 1]` (over-exposed areas lose their hue).
    Clamp,
    /// Reinhard et al., "Photographic Tone Reproduction for Digital Images",
    /// SIGGRAPH 2002, eq. 3 applied to luminance: `c · 1/(1 + L)`, which keeps
    /// the hue and compresses smoothly.
    Reinhard,
    /// The ACES filmic curve, fitted by Narkowicz ("ACES Filmic Tone Mapping
    /// Curve", 2015), per channel.
    Aces,
}

impl ToneMap {
    /// Map a linear colour to `[0, 1]³` (still linear).
    #[inline]
    pub fn apply(self, c: Color) -> Color {
        let c = c.max(Color::ZERO);
        match self {
            ToneMap::Classic => {
                let m = c.max_element();
                if m > 1.0 {
                    c / m
                } else {
                    c
                }
            }
            ToneMap::Clamp => c.min(Color::ONE),
            ToneMap::Reinhard => (c / (1.0 + luminance(c))).min(Color::ONE),
            ToneMap::Aces => {
                let (a, b, cc, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
                ((c * (a * c + b)) / (c * (cc * c + d) + e)).clamp(Color::ZERO, Color::ONE)
            }
        }
    }
}

/// The sRGB transfer function (IEC 61966-2-1): linear `[0,1]` to encoded.
#[inline]
pub fn srgb_encode(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classic_divides_by_the_largest_channel() {
        assert_eq!(ToneMap::Classic.apply(Color::new(2.0, 1.0, 0.5)), Color::new(1.0, 0.5, 0.25));
        assert_eq!(ToneMap::Classic.apply(Color::new(0.9, 0.1, 0.5)), Color::new(0.9, 0.1, 0.5));
    }

    #[test]
    fn clamp_and_smooth_curves_stay_in_range() {
        assert_eq!(ToneMap::Clamp.apply(Color::new(2.0, 0.5, -1.0)), Color::new(1.0, 0.5, 0.0));
        for tm in [ToneMap::Reinhard, ToneMap::Aces] {
            let mut prev = -1.0;
            for i in 0..100 {
                let v = tm.apply(Color::splat(i as f32 * 0.5)).x;
                assert!((0.0..=1.0).contains(&v) && v >= prev, "{tm:?} not monotone");
                prev = v;
            }
        }
        assert_eq!(ToneMap::Reinhard.apply(Color::ONE), Color::splat(0.5));
    }

    #[test]
    fn srgb_endpoints_and_knee() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.4613).abs() < 1e-3);
    }
}
