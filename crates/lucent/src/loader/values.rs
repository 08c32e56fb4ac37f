//! The values of a scene file that have a range (a radius, a field of view,
//! a colour, a sample count): each is a type that checks its value as it is
//! read, so an error points at the offending value in the file.

use serde::{
    de::{Error as _, Visitor},
    Deserialize, Deserializer,
};
use std::fmt;

/// Reads any number (integer or float). A value of another type is reported
/// as "invalid type: ..., expected WHAT", naming what is accepted.
struct NumberVisitor(&'static str);

impl Visitor<'_> for NumberVisitor {
    type Value = f64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }
}

/// Reads a whole number for a count in `1..=max`; a value of another type
/// (a fraction, a string) is reported with the accepted range.
struct CountVisitor {
    what: &'static str,
    max: u32,
}

impl Visitor<'_> for CountVisitor {
    type Value = i64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: a whole number from 1 to {}", self.what, self.max)
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<i64, E> {
        Ok(v)
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<i64, E> {
        Ok(i64::try_from(v).unwrap_or(i64::MAX))
    }
}

macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, $ok:expr, $what:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
        #[serde(transparent)]
        pub struct $name(pub(super) f32);

        impl $name {
            /// The value.
            pub fn get(self) -> f32 {
                self.0
            }
        }

        impl TryFrom<f32> for $name {
            type Error = String;
            fn try_from(v: f32) -> Result<Self, String> {
                let ok: fn(f32) -> bool = $ok;
                if v.is_finite() && ok(v) {
                    Ok(Self(v))
                } else {
                    Err(format!(concat!("expected ", $what, ", got {}"), v))
                }
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = d.deserialize_f64(NumberVisitor($what))?;
                if v.is_finite() && !(v as f32).is_finite() {
                    return Err(D::Error::custom(format!(
                        concat!("expected ", $what, ", got {:e}, which is too large (at most about 3.4e38)"),
                        v
                    )));
                }
                Self::try_from(v as f32).map_err(D::Error::custom)
            }
        }
    };
}

checked_f32!(
    /// A finite number > 0.
    Positive, |v| v > 0.0, "a number > 0"
);
checked_f32!(
    /// A finite number ≥ 0.
    NonNegative, |v| v >= 0.0, "a number ≥ 0"
);
checked_f32!(
    /// A field of view in degrees, strictly between 0 and 180.
    FieldOfView, |v| v > 0.0 && v < 180.0, "a field of view strictly between 0 and 180 degrees"
);
checked_f32!(
    /// Any finite number.
    Finite, |_| true, "a finite number"
);

/// Three finite numbers: a point or a free vector.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct Vec3Desc(pub [f32; 3]);

impl<'de> Deserialize<'de> for Vec3Desc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(Self(<[Finite; 3]>::deserialize(d)?.map(Finite::get)))
    }
}

impl fmt::Display for Vec3Desc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.0;
        write!(f, "[{x}, {y}, {z}]")
    }
}

impl From<Vec3Desc> for glam::Vec3A {
    fn from(v: Vec3Desc) -> Self {
        glam::Vec3A::from_array(v.0)
    }
}

/// Three finite numbers, not all zero: a direction or a normal.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct Direction(pub [f32; 3]);

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec3Desc::deserialize(d)?.0;
        if v.iter().all(|&c| c == 0.0) {
            Err(D::Error::custom("a direction or normal must not be [0, 0, 0]"))
        } else {
            Ok(Self(v))
        }
    }
}

impl From<Direction> for glam::Vec3A {
    fn from(v: Direction) -> Self {
        glam::Vec3A::from_array(v.0)
    }
}

/// A linear RGB colour: three finite numbers ≥ 0 (values above 1 are
/// allowed: they are radiance, not display values).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct Rgb(pub [f32; 3]);

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = <[Finite; 3]>::deserialize(d)?.map(Finite::get);
        if v.iter().all(|c| *c >= 0.0) {
            Ok(Self(v))
        } else {
            Err(D::Error::custom("expected a colour [r, g, b] of finite numbers ≥ 0"))
        }
    }
}

impl From<Rgb> for glam::Vec3A {
    fn from(v: Rgb) -> Self {
        glam::Vec3A::from_array(v.0)
    }
}

/// An image dimension: 1 to 65,536 pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(transparent)]
pub struct ImageDimension(pub u32);

impl<'de> Deserialize<'de> for ImageDimension {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "an image size in pixels", max: crate::film::MAX_DIMENSION })?;
        if (1..=crate::film::MAX_DIMENSION as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!(
                "expected an image size from 1 to {} pixels, got {v}",
                crate::film::MAX_DIMENSION
            )))
        }
    }
}

/// Samples per pixel: at least 1, at most 1,048,576.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(transparent)]
pub struct SampleCount(pub u32);

/// Largest samples-per-pixel count accepted.
pub const MAX_SPP: u32 = 1 << 20;

impl<'de> Deserialize<'de> for SampleCount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "samples per pixel", max: MAX_SPP })?;
        if (1..=MAX_SPP as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!("expected samples per pixel from 1 to {MAX_SPP}, got {v}")))
        }
    }
}

/// Most mirror bounces: 0 to 10,000.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(transparent)]
pub struct MaxDepth(pub u32);

/// Largest `max_depth` accepted. Deeper chains add nothing visible: each
/// bounce multiplies by a reflectivity below 1.
pub const MAX_DEPTH: u32 = 10_000;

impl<'de> Deserialize<'de> for MaxDepth {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_i64(CountVisitor { what: "a bounce count", max: MAX_DEPTH })?;
        if (0..=MAX_DEPTH as i64).contains(&v) {
            Ok(Self(v as u32))
        } else {
            Err(D::Error::custom(format!("expected max_depth from 0 to {MAX_DEPTH}, got {v}")))
        }
    }
}
