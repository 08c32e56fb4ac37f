//! Affine transforms between object space and world space.

use super::{gamma, Bounds3, Ray};
use crate::geometry::Vec3;
use glam::{Mat3, Mat4, Vec4};

/// Why a matrix cannot serve as an object transform.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TransformError {
    /// The matrix has no inverse (a zero scale, say), so rays could not be
    /// taken into object space.
    #[error("the transform is singular (determinant {0:e}); a zero scale or collapsed axis cannot be undone")]
    Singular(f32),
    /// The bottom row is not `[0, 0, 0, 1]`: projective transforms are not
    /// supported.
    #[error("the bottom row of a matrix must be [0, 0, 0, 1] (affine transforms only)")]
    NotAffine,
    /// An entry is infinite or NaN.
    #[error("the transform has a non-finite entry")]
    NonFinite,
    /// A given inverse is not the matrix's inverse.
    #[error("the inverse given is not the inverse of the matrix (their product differs from the identity by {0:e})")]
    WrongInverse(f32),
}

/// An invertible affine transform, stored with its inverse (the pair `M`,
/// `M⁻¹` as in PBRT). As an object's transform it maps object space to world
/// space.
///
/// Transforms compose in the order they are written: `a.then(&b)` applies
/// `a` first.
///
/// ```
/// use lucent::geometry::{Transform, Vec3};
/// let t = Transform::rotate_z(90.0)
///     .then(&Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap())
///     .then(&Transform::translate(Vec3::new(10.0, 20.0, 0.0)));
/// let p = t.point(Vec3::X);
/// assert!((p - Vec3::new(10.0, 22.0, 0.0)).length() < 1e-5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    m: Mat4,
    m_inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Self = Self { m: Mat4::IDENTITY, m_inv: Mat4::IDENTITY };

    /// A transform from a general 4×4 matrix (column vectors: `p' = M p`).
    pub fn from_matrix(m: Mat4) -> Result<Self, TransformError> {
        if !m.is_finite() {
            return Err(TransformError::NonFinite);
        }
        if m.row(3) != Vec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(TransformError::NotAffine);
        }
        let det = m.determinant();
        // Relative test: compare the determinant with the scale of the matrix
        // so that uniformly tiny (but valid) scales are still accepted.
        let scale = Mat3::from_mat4(m).to_cols_array().iter().fold(0.0f32, |a, v| a.max(v.abs()));
        if det == 0.0 || !det.is_finite() || det.abs() <= 1e-12 * scale.powi(3) {
            return Err(TransformError::Singular(det));
        }
        let m_inv = m.inverse();
        if !m_inv.is_finite() {
            return Err(TransformError::Singular(det));
        }
        Ok(Self { m, m_inv })
    }

    /// A transform from a matrix and its inverse, both given: what a scene
    /// file that stored a transform exactly reads back, bit for bit (an
    /// inverse computed again from the matrix may differ in the last bits).
    /// The matrix is checked as by [`Transform::from_matrix`], and the
    /// inverse must agree with the computed one to single precision:
    /// every entry of `M · M⁻¹ − I` at most 10⁻⁴ (relative to the entries'
    /// magnitude).
    pub fn from_matrix_and_inverse(m: Mat4, m_inv: Mat4) -> Result<Self, TransformError> {
        Self::from_matrix(m)?;
        if !m_inv.is_finite() {
            return Err(TransformError::NonFinite);
        }
        if m_inv.row(3) != Vec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(TransformError::NotAffine);
        }
        let size = |a: &Mat4| a.to_cols_array().iter().fold(0.0f32, |x, v| x.max(v.abs()));
        let error = size(&(m * m_inv - Mat4::IDENTITY));
        // (The product is finite: both matrices are.)
        if error > 1e-4 * (size(&m) * size(&m_inv)).max(1.0) {
            return Err(TransformError::WrongInverse(error));
        }
        Ok(Self { m, m_inv })
    }

    /// Translation by `delta`.
    pub fn translate(delta: Vec3) -> Self {
        Self { m: Mat4::from_translation(delta.into()), m_inv: Mat4::from_translation((-delta).into()) }
    }

    /// Scale by `s` along the axes; a zero component is rejected.
    pub fn scale(s: Vec3) -> Result<Self, TransformError> {
        if s.cmpeq(Vec3::ZERO).any() {
            return Err(TransformError::Singular(s.x * s.y * s.z));
        }
        if !s.is_finite() {
            return Err(TransformError::NonFinite);
        }
        Ok(Self { m: Mat4::from_scale(s.into()), m_inv: Mat4::from_scale(s.recip().into()) })
    }

    /// Rotation by `degrees` about the x axis (right-handed: y towards z).
    pub fn rotate_x(degrees: f32) -> Self {
        Self::rotation(Mat4::from_rotation_x(degrees.to_radians()))
    }

    /// Rotation by `degrees` about the y axis (z towards x).
    pub fn rotate_y(degrees: f32) -> Self {
        Self::rotation(Mat4::from_rotation_y(degrees.to_radians()))
    }

    /// Rotation by `degrees` about the z axis (x towards y).
    pub fn rotate_z(degrees: f32) -> Self {
        Self::rotation(Mat4::from_rotation_z(degrees.to_radians()))
    }

    /// Rotation by `degrees` about an arbitrary `axis` (need not be unit).
    pub fn rotate(axis: Vec3, degrees: f32) -> Result<Self, TransformError> {
        let len = axis.length();
        if len == 0.0 || !len.is_finite() {
            return Err(TransformError::Singular(0.0));
        }
        Ok(Self::rotation(Mat4::from_axis_angle((axis / len).into(), degrees.to_radians())))
    }

    fn rotation(m: Mat4) -> Self {
        // A rotation's inverse is its transpose: exact, no matrix inversion.
        Self { m, m_inv: m.transpose() }
    }

    /// Apply `self`, then `next`.
    pub fn then(&self, next: &Transform) -> Transform {
        Transform { m: next.m * self.m, m_inv: self.m_inv * next.m_inv }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Transform {
        Transform { m: self.m_inv, m_inv: self.m }
    }

    /// The forward matrix.
    pub fn matrix(&self) -> Mat4 {
        self.m
    }

    /// The inverse matrix.
    pub fn inverse_matrix(&self) -> Mat4 {
        self.m_inv
    }

    /// Whether this is exactly the identity.
    pub fn is_identity(&self) -> bool {
        self.m == Mat4::IDENTITY
    }

    /// Transform a point.
    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.transform_point3a(p)
    }

    /// Transform a direction (no translation).
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3a(v)
    }

    /// Transform a surface normal: by the inverse transpose, so that it stays
    /// perpendicular to transformed tangents. The result is not normalised.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        // (M⁻¹)ᵀ n, written out from the columns of M⁻¹.
        let c = &self.m_inv;
        Vec3::new(Vec3::from_vec4(c.x_axis).dot(n), Vec3::from_vec4(c.y_axis).dot(n), Vec3::from_vec4(c.z_axis).dot(n))
    }

    /// Take a world-space ray into this transform's object space. The
    /// direction is not renormalised, so hit distances `t` agree in both
    /// spaces.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray::new(self.m_inv.transform_point3a(ray.origin), self.m_inv.transform_vector3a(ray.dir))
    }

    /// Transform a point known to within `error` per component, returning the
    /// point and a conservative bound on its new error (PBRT 4th ed., §6.8.4:
    /// `(γ₃+1)|M|δ + γ₃(|M||p| + |t|)`).
    #[inline]
    pub fn point_with_error(&self, p: Vec3, error: Vec3) -> (Vec3, Vec3) {
        let abs3 = Mat3::from_mat4(self.m).abs();
        let translation = Vec3::from_vec4(self.m.w_axis).abs();
        let g3 = gamma(3);
        let out_err = (g3 + 1.0) * (abs3 * error) + g3 * (abs3 * p.abs() + translation);
        (self.point(p), out_err)
    }

    /// World bounds of an object-space box: the box around its eight
    /// transformed corners. Infinite boxes stay infinite.
    pub fn bounds(&self, b: &Bounds3) -> Bounds3 {
        if b.is_infinite() {
            return Bounds3::INFINITE;
        }
        b.corners().iter().fold(Bounds3::EMPTY, |acc, &c| acc.union_point(self.point(c)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn composition_order_is_the_written_order() {
        // rotate, then translate: a point on x rotates onto y, then moves.
        let t = Transform::rotate_z(90.0).then(&Transform::translate(Vec3::new(5.0, 0.0, 0.0)));
        assert!((t.point(Vec3::X) - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-6);
        let back = t.inverse().point(t.point(Vec3::new(0.3, -2.0, 7.0)));
        assert!((back - Vec3::new(0.3, -2.0, 7.0)).length() < 1e-5);
    }

    #[test]
    fn normals_stay_perpendicular_under_nonuniform_scale() {
        let t = Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap();
        let tangent = Vec3::new(1.0, -1.0, 0.0);
        let n = Vec3::new(1.0, 1.0, 0.0);
        assert!(t.vector(tangent).dot(t.normal(n)).abs() < 1e-6);
    }

    #[test]
    fn singular_and_projective_matrices_are_refused() {
        assert!(Transform::scale(Vec3::new(1.0, 0.0, 1.0)).is_err());
        assert!(matches!(Transform::from_matrix(Mat4::ZERO), Err(TransformError::NotAffine)));
        let mut m = Mat4::IDENTITY;
        m.x_axis = Vec4::ZERO;
        assert!(matches!(Transform::from_matrix(m), Err(TransformError::Singular(_))));
        let mut p = Mat4::IDENTITY;
        p.x_axis.w = 1.0;
        assert_eq!(Transform::from_matrix(p), Err(TransformError::NotAffine));
    }

    #[test]
    fn point_error_bound_covers_the_rounding() {
        let t = Transform::rotate(Vec3::new(1.0, 2.0, 3.0), 37.0)
            .unwrap()
            .then(&Transform::translate(Vec3::new(1e3, -2e3, 5.0)));
        let p = Vec3::new(1.2345, -6.789, 0.5);
        let (q, err) = t.point_with_error(p, Vec3::ZERO);
        let exact = t.matrix().as_dmat4().transform_point3(p.as_dvec3());
        for i in 0..3 {
            assert!((q[i] as f64 - exact[i]).abs() <= err[i] as f64);
        }
    }
}
