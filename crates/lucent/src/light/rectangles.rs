//! Emissive quads as one rectangular light each.
//!
//! A quad of a scene file, or a two-triangle patch of a pbrt-v4 mesh, is
//! two triangles, and the scene builder first makes one area light per
//! triangle. Sampling such a light means choosing one triangle and then a
//! spherical triangle (Arvo 1995), which costs two inverse trigonometric
//! solid angles and an alias-table lookup. When the two triangles are the
//! halves of a rectangle, one spherical-rectangle sample (Ureña et al.
//! 2013, [`crate::sampling::SphericalRectangle`]) covers the whole light
//! with the same density `1/Ω` over its solid angle: this pass merges
//! such pairs into one light with a [`Rectangle`] shape, which both
//! triangles then refer to.

use super::AreaLight;
use crate::geometry::Vec3;
use crate::shapes::{Rectangle, Shape};

/// `lights` with every pair of consecutive triangle lights that form a
/// rectangle (same radiance and sides, no emission texture, the same
/// winding) merged into one rectangle light, and the new index of each old
/// light; `None` when nothing merges.
pub(crate) fn merge_rectangles(lights: &[AreaLight]) -> Option<(Vec<AreaLight>, Vec<u32>)> {
    let mut merged = Vec::with_capacity(lights.len());
    let mut remap = Vec::with_capacity(lights.len());
    let mut i = 0;
    let mut any = false;
    while i < lights.len() {
        if let Some(rect) = lights.get(i + 1).and_then(|next| rectangle_of(&lights[i], next)) {
            let index = merged.len() as u32;
            remap.extend([index, index]);
            merged.push(AreaLight { shape: Shape::Rectangle(rect), ..lights[i].clone() });
            any = true;
            i += 2;
        } else {
            remap.push(merged.len() as u32);
            merged.push(lights[i].clone());
            i += 1;
        }
    }
    any.then_some((merged, remap))
}

/// The rectangle two triangle lights form, if they are the two halves of
/// one (sharing a diagonal) and emit alike, oriented as the triangles.
fn rectangle_of(a: &AreaLight, b: &AreaLight) -> Option<Rectangle> {
    let (Shape::Triangle(ta), Shape::Triangle(tb)) = (&a.shape, &b.shape) else { return None };
    if a.radiance != b.radiance
        || a.two_sided != b.two_sided
        || a.reverse != b.reverse
        || a.image.is_some()
        || b.image.is_some()
    {
        return None;
    }
    let (va, vb) = (ta.vertices(), tb.vertices());
    // The shared diagonal: two corners of `a` that are corners of `b`.
    let shared: Vec<Vec3> = va.iter().copied().filter(|p| vb.contains(p)).collect();
    let [s0, s1] = shared[..] else { return None };
    let x = *va.iter().find(|p| **p != s0 && **p != s1)?;
    let y = *vb.iter().find(|p| **p != s0 && **p != s1)?;
    // A quadrilateral is a rectangle when its diagonals bisect each other
    // (a parallelogram, hence planar) and have the same length.
    let scale = (s0 - s1).length();
    let tol = 1e-5 * scale.max(s0.abs().max_element()).max(s1.abs().max_element());
    if ((s0 + s1) - (x + y)).length() > 2.0 * tol || ((s0 - s1).length() - (x - y).length()).abs() > 2.0 * tol {
        return None;
    }
    // Both halves must face the same way, and the rectangle with them.
    let (na, nb) = (ta.front_side(), tb.front_side());
    if na.dot(nb) <= 0.0 {
        return None;
    }
    let (ex, ey) = if (s0 - x).cross(s1 - x).dot(na) > 0.0 { (s0 - x, s1 - x) } else { (s1 - x, s0 - x) };
    Rectangle::new(x, ex, ey).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use crate::shapes::Triangle;

    fn light(v: [Vec3; 3], radiance: f32) -> AreaLight {
        AreaLight {
            shape: Shape::Triangle(Triangle::new(v, None).unwrap()),
            radiance: Color::splat(radiance),
            two_sided: false,
            reverse: false,
            image: None,
        }
    }

    /// The quad (v0, v1, v2, v3) as the loader splits it.
    fn quad(v: [Vec3; 4], radiance: f32) -> [AreaLight; 2] {
        [light([v[0], v[1], v[2]], radiance), light([v[0], v[2], v[3]], radiance)]
    }

    #[test]
    fn a_rectangular_quad_becomes_one_light_with_the_same_area_and_side() {
        let v = [
            Vec3::new(-0.24, 1.98, -0.22),
            Vec3::new(-0.24, 1.98, 0.16),
            Vec3::new(0.23, 1.98, 0.16),
            Vec3::new(0.23, 1.98, -0.22),
        ];
        let [a, b] = quad(v, 4.0);
        let front = a.shape.front_side(v[0]);
        let single = light([Vec3::ZERO, Vec3::X, Vec3::Y], 1.0);
        let lights = vec![single.clone(), a.clone(), b.clone(), single];
        let (merged, remap) = merge_rectangles(&lights).unwrap();
        assert_eq!(remap, vec![0, 1, 1, 2]);
        assert_eq!(merged.len(), 3);
        let Shape::Rectangle(r) = &merged[1].shape else { panic!("not a rectangle: {:?}", merged[1].shape) };
        assert!((r.area() - (a.area() + b.area())).abs() < 1e-6);
        assert!((merged[1].power() - (a.power() + b.power())).abs() < 1e-5 * merged[1].power());
        assert!(r.normal().dot(front.normalize()) > 0.999_999);
        assert_eq!(merged[1].radiance, Color::splat(4.0));
    }

    #[test]
    fn other_pairs_stay_triangles() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let kite = [Vec3::ZERO, Vec3::X, Vec3::new(1.5, 1.5, 0.0), Vec3::Y];
        let sheared = [Vec3::ZERO, Vec3::X, Vec3::new(1.5, 1.0, 0.0), Vec3::new(0.5, 1.0, 0.0)];
        // Not rectangles.
        assert!(merge_rectangles(&quad(kite, 1.0)).is_none());
        assert!(merge_rectangles(&quad(sheared, 1.0)).is_none());
        // Different radiance, or an emission side that differs.
        let [a, b] = quad(square, 1.0);
        assert!(merge_rectangles(&[a.clone(), AreaLight { radiance: Color::splat(2.0), ..b.clone() }]).is_none());
        assert!(merge_rectangles(&[a.clone(), AreaLight { two_sided: true, ..b.clone() }]).is_none());
        // Halves wound opposite ways.
        let flipped = light([square[0], square[3], square[2]], 1.0);
        assert!(merge_rectangles(&[a.clone(), flipped]).is_none());
        // Not sharing a diagonal.
        let apart = light([Vec3::new(5.0, 0.0, 0.0), Vec3::new(6.0, 0.0, 0.0), Vec3::new(5.0, 1.0, 0.0)], 1.0);
        assert!(merge_rectangles(&[a, apart]).is_none());
        assert!(merge_rectangles(&[b]).is_none());
    }
}
