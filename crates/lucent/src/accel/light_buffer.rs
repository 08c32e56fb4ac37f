//! The light buffer of Haines & Greenberg ("The Light Buffer: A
//! Shadow-Testing Accelerator", IEEE CG&A 6(9), 1986): for a light at a
//! point, a cube of direction cells around it, each listing the primitives
//! that some direction of the cell may meet.
//!
//! A shadow ray from a surface point `p` to the light runs along one
//! direction seen from the light, `p − light`, so only the primitives of
//! that direction's cell can block it: the query is a table lookup and a
//! few primitive tests, with no box tests and no traversal. For scenes of a
//! handful of primitives (the classic renderer's), where a shadow ray from
//! an open floor has nothing to test at all. The lists are bit sets, so a
//! buffer serves at most [`LightBuffer::MAX_PRIMITIVES`] primitives; larger
//! scenes keep their BVH.
//!
//! Each cube face is the plane one unit from the light along `±x`, `±y` or
//! `±z`, cut into `RES × RES` square cells of its `[−1, 1]²` coordinates;
//! a direction `d` belongs to the face of its largest component and to the
//! cell of `(d_u / |d_a|, d_v / |d_a|)` there. A primitive is entered in
//! every cell its bounding box may project into: where the box lies wholly
//! in front of a face, the central projection of the box is inside the
//! rectangle spanned by its eight projected corners (the projection of a
//! convex set is the hull of its projected corners), widened by a margin
//! for rounding; where the box reaches the light's side of the face plane,
//! the whole face.

use crate::geometry::{Bounds3, Vec3};

/// Cells along each edge of a cube face.
const RES: usize = 32;

/// How far a projected rectangle is widened, in face coordinates (the
/// face spans 2): far more than the rounding of one division, so that a
/// direction on a cell border is in the cells on both sides.
const MARGIN: f32 = 1e-3;

/// The direction cells around one light (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct LightBuffer {
    light: Vec3,
    /// `6 · RES · RES` bit sets: bit `i` is primitive `i` of the bounds the
    /// buffer was built from. Face `2·axis + (negative as usize)`, then row
    /// `v`, then column `u`.
    cells: Vec<u64>,
}

/// The two axes of a face's coordinates, for the face's axis.
const FACE_AXES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];

impl LightBuffer {
    /// The most primitives a buffer can list.
    pub const MAX_PRIMITIVES: usize = 64;

    /// The buffer of a light at `light` over the boxes `bounds`
    /// (primitive `i` has `bounds[i]`); `None` if there are more than
    /// [`LightBuffer::MAX_PRIMITIVES`] or a box is not finite.
    pub fn build(light: Vec3, bounds: &[Bounds3]) -> Option<Self> {
        if bounds.len() > Self::MAX_PRIMITIVES || !light.is_finite() {
            return None;
        }
        if bounds.iter().any(|b| !(b.min.is_finite() && b.max.is_finite())) {
            return None;
        }
        let mut cells = vec![0u64; 6 * RES * RES];
        for (i, b) in bounds.iter().enumerate() {
            if b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z {
                continue; // empty: nothing to hit
            }
            let bit = 1u64 << i;
            let corners: [Vec3; 8] = std::array::from_fn(|k| {
                Vec3::new(
                    if k & 1 == 0 { b.min.x } else { b.max.x },
                    if k & 2 == 0 { b.min.y } else { b.max.y },
                    if k & 4 == 0 { b.min.z } else { b.max.z },
                ) - light
            });
            for face in 0..6 {
                let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
                let (a1, a2) = FACE_AXES[axis];
                let range = if corners.iter().all(|c| sign * c[axis] > 0.0) {
                    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
                    for c in &corners {
                        let w = sign * c[axis];
                        for (k, a) in [a1, a2].into_iter().enumerate() {
                            let t = c[a] / w;
                            lo[k] = lo[k].min(t);
                            hi[k] = hi[k].max(t);
                        }
                    }
                    if lo[0] > 1.0 + MARGIN || lo[1] > 1.0 + MARGIN || hi[0] < -1.0 - MARGIN || hi[1] < -1.0 - MARGIN {
                        continue; // projects outside this face
                    }
                    let cell = |t: f32| cell_index(t);
                    [cell(lo[0] - MARGIN), cell(hi[0] + MARGIN), cell(lo[1] - MARGIN), cell(hi[1] + MARGIN)]
                } else if corners.iter().all(|c| sign * c[axis] <= 0.0) {
                    continue; // wholly behind the face plane
                } else {
                    [0, RES - 1, 0, RES - 1]
                };
                let [u0, u1, v0, v1] = range;
                for v in v0..=v1 {
                    for u in u0..=u1 {
                        cells[(face * RES + v) * RES + u] |= bit;
                    }
                }
            }
        }
        Some(Self { light, cells })
    }

    /// The light's position.
    pub fn light(&self) -> Vec3 {
        self.light
    }

    /// The primitives (as a bit set over the build's `bounds`) that may
    /// meet the segment from the light to `p`: every one whose box that
    /// segment crosses is in it. All of them where `p` is the light itself
    /// or not finite.
    #[inline]
    pub fn candidates(&self, p: Vec3) -> u64 {
        let d = p - self.light;
        let a = d.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let w = a[axis];
        if !(w > 0.0 && w.is_finite()) {
            return u64::MAX;
        }
        let face = 2 * axis + (d[axis] < 0.0) as usize;
        let (a1, a2) = FACE_AXES[axis];
        // One reciprocal: its rounding moves a coordinate by far less than
        // the margin the cells were widened by.
        let inv = 1.0 / w;
        let (u, v) = (cell_index(d[a1] * inv), cell_index(d[a2] * inv));
        self.cells[(face * RES + v) * RES + u]
    }

    /// Heap bytes.
    pub fn memory_bytes(&self) -> usize {
        self.cells.capacity() * std::mem::size_of::<u64>()
    }
}

/// The cell of face coordinate `t` (in `[−1, 1]`; clamped outside).
#[inline]
fn cell_index(t: f32) -> usize {
    // Truncation is the floor for the non-negative values that matter, and
    // `as` saturates: NaN and negatives give 0. (`floor` is a library call
    // on baseline x86-64, which has no rounding instruction.)
    (((t + 1.0) * (0.5 * RES as f32)) as usize).min(RES - 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    fn rand_vec(rng: &mut Pcg32, s: f32) -> Vec3 {
        Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * (2.0 * s)
    }

    /// Whether the segment from `a` to `b` meets the box (slab test in f64).
    fn segment_meets(a: Vec3, b: Vec3, bx: &Bounds3) -> bool {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            let (o, d) = (a[k] as f64, (b[k] - a[k]) as f64);
            let (lo, hi) = (bx.min[k] as f64, bx.max[k] as f64);
            if d == 0.0 {
                if o < lo || o > hi {
                    return false;
                }
                continue;
            }
            let (mut n, mut f) = ((lo - o) / d, (hi - o) / d);
            if n > f {
                std::mem::swap(&mut n, &mut f);
            }
            t0 = t0.max(n);
            t1 = t1.min(f);
        }
        t0 <= t1
    }

    /// Conservative: a box that the segment from the light to a point
    /// crosses is always among the candidates; and the buffer does cull
    /// (most points see few of the boxes).
    #[test]
    fn every_box_the_segment_crosses_is_a_candidate() {
        let mut rng = Pcg32::new(9, 4);
        let mut culled = 0u64;
        let mut total = 0u64;
        for round in 0..20 {
            let boxes: Vec<Bounds3> = (0..40)
                .map(|_| {
                    let c = rand_vec(&mut rng, 5.0);
                    Bounds3::from_points(c - rand_vec(&mut rng, 0.8).abs(), c + rand_vec(&mut rng, 0.8).abs())
                })
                .collect();
            // Some lights inside a box, some on a box's face plane.
            let light = match round % 4 {
                0 => boxes[0].min + 0.5 * (boxes[0].max - boxes[0].min),
                1 => Vec3::new(boxes[1].min.x, rand_vec(&mut rng, 5.0).y, rand_vec(&mut rng, 5.0).z),
                _ => rand_vec(&mut rng, 7.0),
            };
            let buffer = LightBuffer::build(light, &boxes).unwrap();
            for _ in 0..4000 {
                // Points anywhere, and points on the axes' diagonals (cell
                // and face borders).
                let p = if rng.uniform() < 0.1 {
                    let s = rng.uniform() * 6.0;
                    light + Vec3::new(s, if rng.uniform() < 0.5 { s } else { -s }, rng.uniform() * s)
                } else {
                    rand_vec(&mut rng, 8.0)
                };
                let c = buffer.candidates(p);
                for (i, b) in boxes.iter().enumerate() {
                    total += 1;
                    if segment_meets(light, p, b) {
                        assert!(c & (1 << i) != 0, "box {i} {b:?} missed, light {light:?}, p {p:?}");
                    } else if c & (1 << i) == 0 {
                        culled += 1;
                    }
                }
            }
        }
        assert!(culled * 2 > total, "culled only {culled} of {total}");
    }

    #[test]
    fn too_many_or_unbounded_primitives_get_no_buffer() {
        let b = Bounds3::from_points(Vec3::ZERO, Vec3::ONE);
        assert!(LightBuffer::build(Vec3::splat(3.0), &vec![b; 65]).is_none());
        assert!(LightBuffer::build(Vec3::splat(3.0), &vec![b; 64]).is_some());
        assert!(LightBuffer::build(Vec3::splat(3.0), &[b, Bounds3::INFINITE]).is_none());
        let at_light = LightBuffer::build(Vec3::splat(3.0), &[b]).unwrap();
        assert_eq!(at_light.candidates(Vec3::splat(3.0)), u64::MAX);
    }
}
