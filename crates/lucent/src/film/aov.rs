//! Auxiliary images (AOVs, "arbitrary output variables"): per-pixel
//! averages of what the camera sees besides radiance, for denoisers and
//! compositing.
//!
//! A render asks for a set of them ([`AovSet`]); every camera sample then
//! also records an [`AovSample`], and the film averages it with the same
//! filter weights as the colour, in the same exact fixed-point sums (see
//! [`Accumulator`](super::Accumulator)), so the layers go through
//! checkpoints, partial renders and merging exactly as the colour does.
//!
//! The layers are named as pbrt-v4's `GBufferFilm` names its EXR channels:
//!
//! | AOV | channels | what |
//! |---|---|---|
//! | `albedo` | `Albedo.R/G/B` | reflectance of the first surface that is not a perfect mirror or smooth glass |
//! | `normal` | `Ns.X/Y/Z` | its shading normal, world space, facing the viewer |
//! | `position` | `P.X/Y/Z` | the first surface the camera ray hits, world space |
//! | `depth` | `Z` | distance from the camera ray's origin to that surface |
//!
//! Where the camera ray escapes, position, depth and normal are 0 (as
//! pbrt-v4's `GBufferFilm` leaves them) and the albedo is the environment's
//! radiance clamped to 1 (black without one).

use std::fmt;
use std::str::FromStr;

use crate::color::Color;
use crate::geometry::Vec3;

/// One auxiliary image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// Surface reflectance, `Albedo.R/G/B`.
    Albedo,
    /// Shading normal in world space, `Ns.X/Y/Z`.
    Normal,
    /// Hit position in world space, `P.X/Y/Z`.
    Position,
    /// Distance from the camera, `Z`.
    Depth,
}

impl Aov {
    /// Every AOV, in the order their channels are stored.
    pub const ALL: [Aov; 4] = [Aov::Albedo, Aov::Normal, Aov::Position, Aov::Depth];

    /// The name used on the command line, in scene files and in Python.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Position => "position",
            Aov::Depth => "depth",
        }
    }

    /// Its EXR channel names.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Albedo => &["Albedo.R", "Albedo.G", "Albedo.B"],
            Aov::Normal => &["Ns.X", "Ns.Y", "Ns.Z"],
            Aov::Position => &["P.X", "P.Y", "P.Z"],
            Aov::Depth => &["Z"],
        }
    }

    fn bit(self) -> u32 {
        1 << Aov::ALL.iter().position(|&a| a == self).expect("listed")
    }
}

impl fmt::Display for Aov {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An AOV name that is not one of lucent's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown auxiliary image '{0}' (accepted: albedo, normal, position, depth)")]
pub struct UnknownAov(pub String);

impl FromStr for Aov {
    type Err = UnknownAov;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Aov::ALL.into_iter().find(|a| a.name() == s.trim()).ok_or_else(|| UnknownAov(s.trim().to_owned()))
    }
}

/// A set of AOVs. Their channels are always stored in the order of
/// [`Aov::ALL`], whatever the order they were asked for in.
///
/// The set also says whether the film keeps a *light image* after the AOV
/// channels ([`AovSet::with_light_image`]): the splats of light-tracing
/// strategies of bidirectional path tracing, three sums per pixel that are
/// not averaged but added to the colour (see
/// [`Accumulator`](super::Accumulator)). It is no AOV (it is never listed,
/// named or written as a layer), but it travels with them through
/// checkpoints and partial renders, which store the set.
///
/// ```
/// use lucent::film::{Aov, AovSet};
/// let set: AovSet = "depth,albedo".parse().unwrap();
/// assert_eq!(set.iter().collect::<Vec<_>>(), [Aov::Albedo, Aov::Depth]);
/// assert_eq!(set.channel_names(), ["Albedo.R", "Albedo.G", "Albedo.B", "Z"]);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AovSet(u32);

impl AovSet {
    /// No AOVs.
    pub const NONE: AovSet = AovSet(0);

    /// The set holding `aovs`.
    pub fn of(aovs: &[Aov]) -> Self {
        AovSet(aovs.iter().fold(0, |bits, a| bits | a.bit()))
    }

    /// The bit of the light image (after the AOVs' bits).
    const LIGHT_IMAGE: u32 = 1 << Aov::ALL.len();

    /// Whether the set holds no AOV (a light image does not count).
    pub fn is_empty(self) -> bool {
        self.0 & !Self::LIGHT_IMAGE == 0
    }

    /// The set with the light image of bidirectional path tracing added
    /// (see the type's docs).
    pub fn with_light_image(self) -> Self {
        AovSet(self.0 | Self::LIGHT_IMAGE)
    }

    /// The set without the light image: the AOVs alone.
    pub fn without_light_image(self) -> Self {
        AovSet(self.0 & !Self::LIGHT_IMAGE)
    }

    /// Whether the film keeps a light image.
    pub fn has_light_image(self) -> bool {
        self.0 & Self::LIGHT_IMAGE != 0
    }

    /// Values stored per pixel after the colour's four sums: the AOV
    /// channels, then 3 for the light image if held.
    pub fn stored_channels(self) -> usize {
        self.channel_count() + if self.has_light_image() { 3 } else { 0 }
    }

    /// Whether `aov` is in the set.
    pub fn contains(self, aov: Aov) -> bool {
        self.0 & aov.bit() != 0
    }

    /// Every AOV of either set.
    pub fn union(self, other: AovSet) -> Self {
        AovSet(self.0 | other.0)
    }

    /// The set with `aov` added.
    pub fn with(self, aov: Aov) -> Self {
        AovSet(self.0 | aov.bit())
    }

    /// The AOVs in storage order.
    pub fn iter(self) -> impl Iterator<Item = Aov> {
        Aov::ALL.into_iter().filter(move |&a| self.contains(a))
    }

    /// Channels stored per pixel.
    pub fn channel_count(self) -> usize {
        self.iter().map(|a| a.channels().len()).sum()
    }

    /// The EXR channel names, in storage order.
    pub fn channel_names(self) -> Vec<&'static str> {
        self.iter().flat_map(|a| a.channels().iter().copied()).collect()
    }

    /// The set as stored in files (bit `i` for `Aov::ALL[i]`).
    pub fn bits(self) -> u32 {
        self.0
    }

    /// The set stored as `bits`, if every bit names an AOV.
    pub fn from_bits(bits: u32) -> Option<Self> {
        (bits >> (Aov::ALL.len() + 1) == 0).then_some(AovSet(bits))
    }

    /// Where `aov`'s first channel lies among the set's channels.
    pub fn offset(self, aov: Aov) -> Option<usize> {
        self.contains(aov).then(|| self.iter().take_while(|&a| a != aov).map(|a| a.channels().len()).sum())
    }

    /// The channels of `sample` that the set holds, in storage order, into
    /// `out` (of [`channel_count`](Self::channel_count) values).
    pub fn write(self, sample: &AovSample, out: &mut [f32]) {
        let mut i = 0;
        for aov in self.iter() {
            let values: &[f32] = match aov {
                Aov::Albedo => &sample.albedo.to_array(),
                Aov::Normal => &sample.normal.to_array(),
                Aov::Position => &sample.position.to_array(),
                Aov::Depth => &[sample.depth],
            };
            out[i..i + values.len()].copy_from_slice(values);
            i += values.len();
        }
    }
}

impl fmt::Display for AovSet {
    /// The names, comma-separated (`none` for the empty set).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return f.write_str("none");
        }
        let names: Vec<_> = self.iter().map(Aov::name).collect();
        f.write_str(&names.join(","))
    }
}

impl FromStr for AovSet {
    type Err = UnknownAov;

    /// Comma-separated names; empty or `none` for no AOVs.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim().is_empty() || s.trim() == "none" {
            return Ok(AovSet::NONE);
        }
        s.split(',').try_fold(AovSet::NONE, |set, name| Ok(set.with(name.parse()?)))
    }
}

/// What one camera sample records besides radiance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AovSample {
    /// Reflectance of the first surface that is not a perfect mirror or
    /// smooth glass, times the tint of the mirrors and glass on the way.
    pub albedo: Color,
    /// That surface's shading normal (world space, facing the ray), or 0.
    pub normal: Vec3,
    /// The first hit, world space, or 0.
    pub position: Vec3,
    /// Distance from the ray's origin to the first hit, or 0.
    pub depth: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_parse_print_and_lay_out_channels() {
        let all: AovSet = "albedo, normal,position ,depth".parse().unwrap();
        assert_eq!(all.channel_count(), 10);
        assert_eq!(all.to_string(), "albedo,normal,position,depth");
        assert_eq!(all.offset(Aov::Position), Some(6));
        assert_eq!(AovSet::of(&[Aov::Depth, Aov::Normal]).offset(Aov::Depth), Some(3));
        assert_eq!(AovSet::of(&[Aov::Depth]).offset(Aov::Normal), None);
        assert_eq!("none".parse::<AovSet>().unwrap(), AovSet::NONE);
        assert_eq!(AovSet::from_bits(all.bits()), Some(all));
        assert_eq!(AovSet::from_bits(1 << 5), None);
        let light = AovSet::of(&[Aov::Depth]).with_light_image();
        assert_eq!(AovSet::from_bits(light.bits()), Some(light));
        assert!(AovSet::NONE.with_light_image().is_empty() && light.has_light_image());
        assert_eq!((light.channel_count(), light.stored_channels()), (1, 4));
        assert_eq!((light.to_string(), light.without_light_image()), ("depth".to_owned(), AovSet::of(&[Aov::Depth])));
        let e = "albedo,colour".parse::<AovSet>().unwrap_err();
        assert_eq!(e.to_string(), "unknown auxiliary image 'colour' (accepted: albedo, normal, position, depth)");
        let sample = AovSample {
            albedo: Color::new(0.1, 0.2, 0.3),
            normal: Vec3::Z,
            position: Vec3::new(4.0, 5.0, 6.0),
            depth: 7.0,
        };
        let mut out = [0.0; 4];
        AovSet::of(&[Aov::Depth, Aov::Albedo]).write(&sample, &mut out);
        assert_eq!(out, [0.1, 0.2, 0.3, 7.0]);
    }
}
