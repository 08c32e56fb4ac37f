use super::{check_finite, ShapeError, ShapeHit};
use crate::geometry::{coordinate_system, gamma, Ray, Vec2, Vec3};
use crate::mesh::VertexAttributes;

/// An infinite plane through a point with a normal.
///
/// Texture coordinates are distances along two fixed tangent directions of
/// the plane, measured from its point, so a checker texture on a plane has
/// squares of `scale` world units.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    point: Vec3,
    normal: Vec3,
    tangent_u: Vec3,
    tangent_v: Vec3,
}

impl Plane {
    /// A plane through `point` perpendicular to `normal` (need not be unit).
    pub fn new(point: Vec3, normal: Vec3) -> Result<Self, ShapeError> {
        let len = check_finite(normal)?.length();
        if len == 0.0 || !len.is_finite() {
            return Err(ShapeError::ZeroNormal);
        }
        let normal = normal / len;
        let (tangent_u, tangent_v) = coordinate_system(normal);
        Ok(Self { point: check_finite(point)?, normal, tangent_u, tangent_v })
    }

    /// The point given at construction.
    pub fn point(&self) -> Vec3 {
        self.point
    }

    /// The unit normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The ray parameter of the intersection with `0 < t < t_max`, if any:
    /// `t = (p₀ - o)·n / d·n`. Shadow rays need no more than this.
    #[inline]
    pub fn intersect_t(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let denom = ray.dir.dot(self.normal);
        if denom == 0.0 {
            return None; // parallel
        }
        let t = (self.point - ray.origin).dot(self.normal) / denom;
        (t > 0.0 && t < t_max).then_some(t)
    }

    /// The intersection with `0 < t < t_max`, if any (see
    /// [`Plane::intersect_t`]).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let t = self.intersect_t(ray, t_max)?;
        // Project the computed point back onto the plane; what remains is the
        // rounding of that projection, bounded relative to the magnitudes
        // involved.
        let mut p = ray.at(t);
        let rel = p - self.point;
        p -= rel.dot(self.normal) * self.normal;
        let p_error = gamma(5) * (p.abs() + self.point.abs());
        let rel = p - self.point;
        let uv = Vec2::new(rel.dot(self.tangent_u), rel.dot(self.tangent_v));
        Some(ShapeHit {
            t,
            p,
            p_error,
            n: self.normal,
            ns: self.normal,
            uv,
            dpdu: self.tangent_u,
            dpdv: self.tangent_v,
            face: 0,
            attributes: VertexAttributes::plain(uv),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_from_either_side() {
        let pl = Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 3.0, 0.0)).unwrap();
        let h = pl.intersect(&Ray::new(Vec3::ZERO, -Vec3::Y), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(h.p, Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(h.n, Vec3::Y);
        let h = pl.intersect(&Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::new(0.0, 2.0, 0.0)), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
    }

    #[test]
    fn parallel_and_receding_rays_miss() {
        let pl = Plane::new(Vec3::ZERO, Vec3::Y).unwrap();
        assert!(pl.intersect(&Ray::new(Vec3::Y, Vec3::X), f32::INFINITY).is_none());
        assert!(pl.intersect(&Ray::new(Vec3::Y, Vec3::Y), f32::INFINITY).is_none());
        // Grazing but not parallel: hits far away.
        let h = pl.intersect(&Ray::new(Vec3::Y, Vec3::new(1000.0, -1.0, 0.0)), f32::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
    }

    #[test]
    fn intersect_t_is_the_distance_of_intersect() {
        let pl = Plane::new(Vec3::new(0.3, -1.0, 0.2), Vec3::new(0.2, 3.0, -0.4)).unwrap();
        for (o, d, t_max) in [
            (Vec3::ZERO, Vec3::new(0.1, -1.0, 0.3), f32::INFINITY),
            (Vec3::ZERO, Vec3::new(0.1, -1.0, 0.3), 0.5),
            (Vec3::new(2.0, -4.0, 1.0), Vec3::new(-0.3, 1.0, 0.0), f32::INFINITY),
            (Vec3::ZERO, Vec3::Y, f32::INFINITY),
            (Vec3::ZERO, Vec3::X, f32::INFINITY),
        ] {
            let ray = Ray::new(o, d);
            assert_eq!(pl.intersect_t(&ray, t_max), pl.intersect(&ray, t_max).map(|h| h.t), "{ray:?} {t_max}");
        }
    }

    #[test]
    fn zero_normal_is_rejected() {
        assert_eq!(Plane::new(Vec3::ZERO, Vec3::ZERO), Err(ShapeError::ZeroNormal));
    }
}
