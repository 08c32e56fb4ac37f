//! Choosing a light to sample.

use super::Emitter;
use crate::geometry::Bounds3;
use crate::sampling::AliasTable;

/// All the lights of a scene, with a distribution for picking one in
/// proportion to its power ([`Emitter::power`]; PBRT 4th ed., §12.6.2).
/// When every light has zero (or unusable) power, they are picked uniformly.
#[derive(Clone, Debug)]
pub struct LightSet {
    emitters: Vec<Emitter>,
    distribution: AliasTable,
    /// Whether some light is a plain rectangle ([`LightSet::has_rectangles`]).
    rectangles: bool,
    /// Whether some light is a plain sphere ([`LightSet::has_spheres`]).
    spheres: bool,
}

impl LightSet {
    /// The lights of a scene bounded by `bounds` (for the power of lights
    /// at infinity; see [`Emitter::power`]).
    pub fn new(emitters: Vec<Emitter>, bounds: &Bounds3) -> Self {
        let powers: Vec<f32> = emitters.iter().map(|e| e.power(bounds)).collect();
        // Infinite powers would swamp the table: count them as the largest
        // finite float (the alias table treats non-finite weights as 0).
        let powers: Vec<f32> = powers.into_iter().map(|p| if p == f32::INFINITY { f32::MAX } else { p }).collect();
        let rectangles = emitters.iter().any(|e| matches!(e, Emitter::Area(a) if a.plain_rectangle().is_some()));
        let spheres = emitters.iter().any(|e| matches!(e, Emitter::Area(a) if a.plain_sphere().is_some()));
        Self { emitters, distribution: AliasTable::new(&powers), rectangles, spheres }
    }

    /// Whether some light is a rectangle area light without an emission
    /// texture (for which the path integrator samples many vertices at
    /// once).
    #[inline]
    pub fn has_rectangles(&self) -> bool {
        self.rectangles
    }

    /// Whether some light is a sphere area light without an emission
    /// texture (likewise).
    #[inline]
    pub fn has_spheres(&self) -> bool {
        self.spheres
    }

    /// The lights.
    pub fn emitters(&self) -> &[Emitter] {
        &self.emitters
    }

    /// Pick a light with a uniform sample `u` in `[0, 1)`: its index and
    /// probability. `None` only when there are no lights.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        self.distribution.sample(u)
    }

    /// Probability that [`LightSet::sample`] picks light `index` (0 when out
    /// of range).
    pub fn pmf(&self, index: usize) -> f32 {
        self.distribution.pmf(index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use crate::geometry::Vec3;
    use crate::light::{AreaLight, Environment, Falloff, Light};
    use crate::sampling::Pcg32;
    use crate::shapes::{Shape, Triangle};

    fn bounds() -> Bounds3 {
        Bounds3::from_points(Vec3::splat(-1.0), Vec3::splat(1.0))
    }

    #[test]
    fn lights_are_picked_in_proportion_to_power() {
        let emitters = vec![
            Emitter::Delta(Light::point(Vec3::ZERO, Color::ONE, 1.0, Falloff::InverseSquare).unwrap()),
            Emitter::Area(AreaLight {
                shape: Shape::Triangle(Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], None).unwrap()),
                radiance: Color::splat(4.0),
                two_sided: false,
                reverse: false,
                image: None,
            }),
            Emitter::Environment(Environment::Constant(Color::splat(0.1))),
            Emitter::Delta(Light::directional(Vec3::Y, Color::ONE, 0.0).unwrap()),
        ];
        let b = bounds();
        let powers: Vec<f32> = emitters.iter().map(|e| e.power(&b)).collect();
        let total: f32 = powers.iter().sum();
        let set = LightSet::new(emitters, &b);
        let pmf_sum: f32 = (0..4).map(|i| set.pmf(i)).sum();
        assert!((pmf_sum - 1.0).abs() < 1e-6);
        for (i, p) in powers.iter().enumerate() {
            assert!((set.pmf(i) - p / total).abs() < 1e-6, "light {i}");
        }
        assert_eq!(set.pmf(3), 0.0);
        let mut rng = Pcg32::new(2, 2);
        let m = 200_000;
        let mut hist = [0u32; 4];
        for _ in 0..m {
            let (i, p) = set.sample(rng.uniform()).unwrap();
            assert_eq!(p, set.pmf(i));
            hist[i] += 1;
        }
        for i in 0..4 {
            let p = set.pmf(i);
            let sigma = (m as f32 * p * (1.0 - p)).sqrt();
            assert!((hist[i] as f32 - m as f32 * p).abs() <= 5.0 * sigma + 1.0, "light {i}: {hist:?}");
        }
    }

    #[test]
    fn zero_power_lights_are_picked_uniformly_and_no_lights_give_none() {
        let dark = Emitter::Environment(Environment::Constant(Color::ZERO));
        let set = LightSet::new(vec![dark.clone(), dark], &bounds());
        assert_eq!(set.pmf(0), 0.5);
        assert_eq!(set.sample(0.75).unwrap().0, 1);
        let empty = LightSet::new(Vec::new(), &bounds());
        assert!(empty.sample(0.5).is_none());
        assert_eq!(empty.pmf(0), 0.0);
    }
}
