//! Where a quadric (partial sphere, disk, cylinder) sits: an origin and an
//! orthonormal basis. In a primitive's object space it is the identity
//! (pbrt-v4's shapes are defined at the origin around `+z`, PBRT 4th ed.,
//! ch. 6); the world-space copies that area lights sample carry the
//! rotation and translation of a similarity transform here, its scale in
//! the shape's own dimensions.

use crate::geometry::{gamma, Transform, Vec3};

/// An origin and an orthonormal basis: `world = origin + x·ax + y·ay + z·az`.
/// A rigid motion (possibly with a reflection), so distances, ray
/// parameters and areas are the same in both spaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    origin: Vec3,
    axes: [Vec3; 3],
}

impl Placement {
    /// The identity: the shape's own object space.
    pub(crate) const IDENTITY: Placement = Placement { origin: Vec3::ZERO, axes: [Vec3::X, Vec3::Y, Vec3::Z] };

    /// Whether this is the identity (so conversions can be skipped).
    #[inline]
    pub(crate) fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// The origin.
    #[inline]
    pub(crate) fn origin(&self) -> Vec3 {
        self.origin
    }

    /// A point to local coordinates.
    #[inline]
    pub(crate) fn point_to_local(&self, p: Vec3) -> Vec3 {
        if self.is_identity() {
            return p;
        }
        self.vector_to_local(p - self.origin)
    }

    /// A vector to local coordinates.
    #[inline]
    pub(crate) fn vector_to_local(&self, v: Vec3) -> Vec3 {
        if self.is_identity() {
            return v;
        }
        Vec3::new(v.dot(self.axes[0]), v.dot(self.axes[1]), v.dot(self.axes[2]))
    }

    /// A local vector (or normal: the basis is orthonormal) to the outer space.
    #[inline]
    pub(crate) fn vector_to_world(&self, v: Vec3) -> Vec3 {
        if self.is_identity() {
            return v;
        }
        v.x * self.axes[0] + v.y * self.axes[1] + v.z * self.axes[2]
    }

    /// A local point to the outer space.
    #[inline]
    pub(crate) fn point_to_world(&self, p: Vec3) -> Vec3 {
        if self.is_identity() {
            return p;
        }
        self.origin + self.vector_to_world(p)
    }

    /// A local point with its error bound to the outer space, with a
    /// conservative bound on the error of the result (the local error
    /// carried through the basis, plus the rounding of the conversion).
    #[inline]
    pub(crate) fn point_with_error_to_world(&self, p: Vec3, err: Vec3) -> (Vec3, Vec3) {
        if self.is_identity() {
            return (p, err);
        }
        let w = self.point_to_world(p);
        let carried = err.x * self.axes[0].abs() + err.y * self.axes[1].abs() + err.z * self.axes[2].abs();
        let rounding = gamma(4)
            * (self.origin.abs()
                + p.x.abs() * self.axes[0].abs()
                + p.y.abs() * self.axes[1].abs()
                + p.z.abs() * self.axes[2].abs());
        (w, carried * (1.0 + gamma(3)) + rounding)
    }

    /// This placement followed by the similarity transform `t`, with the
    /// transform's uniform scale factor; `None` when `t` is not a
    /// similarity (its linear part is not a rotation, possibly with a
    /// reflection, times one scale), within a relative tolerance of 1e-4.
    pub(crate) fn then(&self, t: &Transform) -> Option<(Placement, f32)> {
        let cols = [t.vector(Vec3::X), t.vector(Vec3::Y), t.vector(Vec3::Z)];
        let s = (cols[0].length() + cols[1].length() + cols[2].length()) / 3.0;
        if !(s > 0.0 && s.is_finite()) {
            return None;
        }
        let tol = 1e-4 * s;
        let similar = cols.iter().all(|c| (c.length() - s).abs() <= tol)
            && cols[0].dot(cols[1]).abs() <= tol * s
            && cols[0].dot(cols[2]).abs() <= tol * s
            && cols[1].dot(cols[2]).abs() <= tol * s;
        if !similar {
            return None;
        }
        let axes = self.axes.map(|a| (t.vector(a) / s).normalize());
        Some((Placement { origin: t.point(self.origin), axes }, s))
    }
}
