//! Participating media: light absorbed, scattered and emitted *inside* a
//! volume (fog, smoke, coloured glass, tea), rather than at surfaces.
//!
//! A [`Medium`] fills space wherever a ray is "in" it. Which medium a ray
//! is in is decided at surfaces, as in pbrt-v4 (PBRT 4th ed., §11.4): a
//! surface may carry a [`MediumInterface`], the medium on the inside (the
//! side opposite its geometric normal) and on the outside (the normal's
//! side). A ray leaving such a surface in direction `w` is in the outside
//! medium when `w · n > 0` and in the inside one otherwise. A surface
//! whose two media are the same is no boundary: rays keep the medium they
//! had. The camera's rays start in the camera's medium. A surface that is
//! only a boundary (a material of kind `interface`) lets rays through,
//! changing their medium; a surface with a material scatters and the
//! scattered ray takes the medium of the side it leaves to.
//!
//! Only homogeneous media are implemented ([`HomogeneousMedium`]), with the
//! Henyey–Greenstein phase function ([`HenyeyGreenstein`]) and pbrt-v4's
//! measured presets ([`measured_medium`]).

mod homogeneous;
mod phase;
mod presets;

pub use homogeneous::{FreeFlight, HomogeneousMedium, MediumEvent};
pub use phase::HenyeyGreenstein;
pub use presets::{measured_medium, measured_medium_names};

use crate::color::Color;
use crate::geometry::Vec3;
use std::num::NonZeroU32;

/// A participating medium.
#[derive(Clone, Debug, PartialEq)]
pub enum Medium {
    /// The same coefficients everywhere.
    Homogeneous(HomogeneousMedium),
}

impl Medium {
    /// Transmittance over distance `d` along a unit direction.
    #[inline]
    pub fn transmittance(&self, d: f32) -> Color {
        match self {
            Medium::Homogeneous(m) => m.transmittance(d),
        }
    }

    /// Where a path of throughput `beta` collides in the medium, drawn
    /// with `u_channel` and `u_distance` (see
    /// [`HomogeneousMedium::free_flight`]).
    #[inline]
    pub fn free_flight(&self, beta: Color, u_channel: f32, u_distance: f32) -> FreeFlight {
        match self {
            Medium::Homogeneous(m) => m.free_flight(beta, u_channel, u_distance),
        }
    }

    /// Sample a ray segment `[0, t_max)` with a free flight drawn before
    /// (see [`HomogeneousMedium::sample_flight`]).
    #[inline]
    pub fn sample_flight(&self, flight: FreeFlight, t_max: f32) -> MediumEvent {
        match self {
            Medium::Homogeneous(m) => m.sample_flight(flight, t_max),
        }
    }

    /// Sample where a ray segment `[0, t_max)` scatters, if it does (see
    /// [`HomogeneousMedium::sample`]).
    #[inline]
    pub fn sample(&self, t_max: f32, beta: Color, u_channel: f32, u_distance: f32) -> MediumEvent {
        match self {
            Medium::Homogeneous(m) => m.sample(t_max, beta, u_channel, u_distance),
        }
    }

    /// The phase function.
    #[inline]
    pub fn phase(&self) -> &HenyeyGreenstein {
        match self {
            Medium::Homogeneous(m) => m.phase(),
        }
    }
}

/// Why a medium cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MediumError {
    /// A coefficient or emission is negative or not finite.
    #[error("medium {0} must be finite and ≥ 0 in every channel, got {1}")]
    Coefficient(&'static str, Color),
    /// The scale is negative or not finite.
    #[error("medium scale must be a finite number ≥ 0, got {0}")]
    Scale(f32),
    /// The phase function's asymmetry is outside (−1, 1).
    #[error("the Henyey–Greenstein asymmetry g must be between -1 and 1 (exclusive), got {0}")]
    Asymmetry(f32),
}

/// A medium of a scene: an index into the scene's list of media
/// (`Scene::media`; stored plus one, so that `Option<MediumId>` takes four
/// bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MediumId(NonZeroU32);

impl MediumId {
    /// The medium at `index` in the scene's list.
    pub fn new(index: usize) -> Self {
        let i = u32::try_from(index).ok().and_then(|i| i.checked_add(1)).expect("fewer than 2³² − 1 media");
        Self(NonZeroU32::new(i).expect("index + 1 > 0"))
    }

    /// The index in the scene's list of media.
    #[inline]
    pub fn index(self) -> usize {
        (self.0.get() - 1) as usize
    }
}

/// The media on the two sides of a surface (`None`: vacuum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    /// The medium on the side opposite the geometric normal.
    pub inside: Option<MediumId>,
    /// The medium on the geometric normal's side.
    pub outside: Option<MediumId>,
}

impl MediumInterface {
    /// No boundary: vacuum on both sides.
    pub const NONE: MediumInterface = MediumInterface { inside: None, outside: None };

    /// A boundary between `inside` and `outside`.
    pub fn new(inside: Option<MediumId>, outside: Option<MediumId>) -> Self {
        Self { inside, outside }
    }

    /// Whether rays crossing the surface change medium (pbrt-v4's
    /// `IsMediumTransition`): the two sides differ.
    #[inline]
    pub fn is_transition(&self) -> bool {
        self.inside != self.outside
    }

    /// The medium a ray leaving the surface (geometric normal `n`) in
    /// direction `w` is in.
    #[inline]
    pub fn medium_along(&self, w: Vec3, n: Vec3) -> Option<MediumId> {
        if w.dot(n) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interfaces_pick_the_side_a_direction_points_to() {
        let (a, b) = (MediumId::new(0), MediumId::new(7));
        assert_eq!((a.index(), b.index()), (0, 7));
        assert_eq!(std::mem::size_of::<MediumInterface>(), 8);
        let mi = MediumInterface::new(Some(a), None);
        assert!(mi.is_transition() && !MediumInterface::NONE.is_transition());
        assert!(!MediumInterface::new(Some(b), Some(b)).is_transition());
        assert_eq!(mi.medium_along(Vec3::Z, Vec3::Z), None);
        assert_eq!(mi.medium_along(-Vec3::Z, Vec3::Z), Some(a));
    }
}
