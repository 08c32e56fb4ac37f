//! The frame and the three ray sets of the raybench protocol
//! (`../shared/tools/raybench/SPEC.md`, sections 2 to 4).
//!
//! Every computation is f64, in exactly the order the protocol writes it,
//! and each ray field is rounded once to f32 (`as f32`, round to nearest,
//! ties to even). Rust never contracts `a * b + c` into a fused
//! multiply-add, and nothing here calls `mul_add`, so the rays are
//! bit-identical to those of the reference (`embree_ref.cpp`) and of the
//! independent checker (`gen_rays.py`). `sin` and `cos` are the C library's
//! (`f64::sin` and `f64::cos` call glibc).

use lucent::geometry::Vec3;

/// Width and height of the primary image, in pixels (1024 × 1024 rays).
pub const IMAGE_SIZE: usize = 1024;
/// Number of primary rays.
pub const NUM_PRIMARY: usize = IMAGE_SIZE * IMAGE_SIZE;
/// Number of incoherent rays.
pub const NUM_INCOHERENT: usize = 1 << 20;
/// Seed of the incoherent set's splitmix64 stream.
pub const SEED_INCOHERENT: u64 = 1;
/// The f64 nearest to π (the protocol's `3.141592653589793`).
const PI: f64 = std::f64::consts::PI;
const TWO_PI: f64 = 2.0 * PI;

/// One ray as traced: eight f32 values, 32 bytes, so that a pass reads
/// each ray with one cache-line access.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct RayRecord {
    /// Origin.
    pub o: [f32; 3],
    /// Direction (not normalized by the tracer).
    pub d: [f32; 3],
    /// Start of the hit interval.
    pub tnear: f32,
    /// End of the hit interval.
    pub tfar: f32,
}

impl RayRecord {
    /// The eight fields in dump order: o, d, tnear, tfar.
    pub fn fields(&self) -> [f32; 8] {
        [self.o[0], self.o[1], self.o[2], self.d[0], self.d[1], self.d[2], self.tnear, self.tfar]
    }
}

/// The mesh's bounding box and the camera frame derived from it (section 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Componentwise minimum of all vertices (exact f32 values).
    pub bmin: [f32; 3],
    /// Componentwise maximum of all vertices.
    pub bmax: [f32; 3],
    /// Centre of the box, f64.
    pub c: [f64; 3],
    /// Extent of the box, f64.
    pub e: [f64; 3],
    /// Length of the box diagonal, f64.
    pub diag: f64,
}

impl Frame {
    /// The frame of `positions` (every vertex counts, used by a triangle or
    /// not); `None` for no vertex.
    pub fn new(positions: &[Vec3]) -> Option<Self> {
        let first = positions.first()?.to_array();
        let (mut bmin, mut bmax) = (first, first);
        for p in positions {
            for a in 0..3 {
                // As C++ std::min / std::max: keep the current value unless
                // the new one is strictly smaller (larger), which also fixes
                // which zero (±0) is kept.
                if p[a] < bmin[a] {
                    bmin[a] = p[a];
                }
                if bmax[a] < p[a] {
                    bmax[a] = p[a];
                }
            }
        }
        let c = std::array::from_fn(|a| 0.5 * (f64::from(bmin[a]) + f64::from(bmax[a])));
        let e: [f64; 3] = std::array::from_fn(|a| f64::from(bmax[a]) - f64::from(bmin[a]));
        let diag = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        Some(Self { bmin, bmax, c, e, diag })
    }
}

/// splitmix64 with wrapping 64-bit arithmetic (section 3).
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A stream seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// `f32(next() >> 40) * 2^-24`, in `[0, 1 - 2^-24]`: exact in f32 and
    /// in f64, so it is returned as the f64 the generators compute with.
    pub fn uniform(&mut self) -> f64 {
        // A 24-bit integer converts to f32 exactly, and the scaling by a
        // power of two is exact too: this is the same value in f64.
        (self.next_u64() >> 40) as f64 * (1.0 / 16_777_216.0)
    }
}

/// The primary set (section 4.1): a 1024 × 1024 pinhole camera at
/// `c + (0, 0, D)` looking down −z, one ray through each pixel centre,
/// row-major from the top-left pixel.
pub fn primary_rays(frame: &Frame) -> Vec<RayRecord> {
    const W: i32 = IMAGE_SIZE as i32;
    const H: i32 = IMAGE_SIZE as i32;
    let t = 2.0_f64.sqrt() - 1.0;
    let o = [frame.c[0] as f32, frame.c[1] as f32, (frame.c[2] + frame.diag) as f32];
    let mut rays = Vec::with_capacity(NUM_PRIMARY);
    for py in 0..H {
        let sy = (f64::from(H - 2 * py - 1) / f64::from(H)) * t;
        for px in 0..W {
            let sx = (f64::from(2 * px + 1 - W) / f64::from(H)) * t;
            let len = (sx * sx + sy * sy + 1.0).sqrt();
            let d = [(sx / len) as f32, (sy / len) as f32, (-1.0 / len) as f32];
            rays.push(RayRecord { o, d, tnear: 0.0, tfar: f32::INFINITY });
        }
    }
    rays
}

/// The incoherent set (section 4.3): origins uniform in the box, directions
/// uniform on the unit sphere (not renormalized after rounding), five draws
/// per ray from one splitmix64 stream seeded with 1.
pub fn incoherent_rays(frame: &Frame) -> Vec<RayRecord> {
    let mut rng = SplitMix64::new(SEED_INCOHERENT);
    let bmin = frame.bmin.map(f64::from);
    let e = frame.e;
    let mut rays = Vec::with_capacity(NUM_INCOHERENT);
    for _ in 0..NUM_INCOHERENT {
        let u1 = rng.uniform();
        let u2 = rng.uniform();
        let u3 = rng.uniform();
        let u4 = rng.uniform();
        let u5 = rng.uniform();
        let o = [(bmin[0] + u1 * e[0]) as f32, (bmin[1] + u2 * e[1]) as f32, (bmin[2] + u3 * e[2]) as f32];
        let z = 1.0 - 2.0 * u4;
        let one_minus = 1.0 - z * z;
        // max(0.0, x) as C++ std::max(0.0, x): 0.0 unless 0.0 < x.
        let r = if 0.0 < one_minus { one_minus } else { 0.0 }.sqrt();
        let phi = TWO_PI * u5;
        let d = [(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32];
        rays.push(RayRecord { o, d, tnear: 0.0, tfar: f32::INFINITY });
    }
    rays
}

/// The shadow set (section 4.2): one ray towards the light for every
/// primary ray that hit, in increasing primary index. `hit_t[k]` is the
/// closest-hit distance of primary ray `k`, `+inf` for a miss. Returns the
/// rays and, for each, the index of the primary ray it starts from.
pub fn shadow_rays(frame: &Frame, primary: &[RayRecord], hit_t: &[f32]) -> (Vec<RayRecord>, Vec<u32>) {
    let h = 0.5 * frame.diag;
    let light = [frame.c[0] + h, frame.c[1] + h, frame.c[2] + h];
    let tnear = (1e-4 * frame.diag) as f32;
    let hits = hit_t.iter().filter(|t| **t < f32::INFINITY).count();
    let mut rays = Vec::with_capacity(hits);
    let mut source = Vec::with_capacity(hits);
    for (k, (ray, &t)) in primary.iter().zip(hit_t).enumerate() {
        // As the reference: skip unless t < +inf (a miss is +inf).
        if t.partial_cmp(&f32::INFINITY) != Some(std::cmp::Ordering::Less) {
            continue;
        }
        let t = f64::from(t);
        let p: [f32; 3] = std::array::from_fn(|a| (f64::from(ray.o[a]) + t * f64::from(ray.d[a])) as f32);
        let v: [f64; 3] = std::array::from_fn(|a| light[a] - f64::from(p[a]));
        let dist = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let d = [(v[0] / dist) as f32, (v[1] / dist) as f32, (v[2] / dist) as f32];
        rays.push(RayRecord { o: p, d, tnear, tfar: dist as f32 });
        source.push(k as u32);
    }
    (rays, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame from bbox bit patterns, as `gen_rays.py --bbox-bits` takes them.
    fn frame_from_bits(bits: [u32; 6]) -> Frame {
        let v = bits.map(f32::from_bits);
        Frame::new(&[Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5])]).unwrap()
    }

    fn bits(r: &RayRecord) -> [u32; 8] {
        r.fields().map(f32::to_bits)
    }

    // The bunny's bbox (bun_zipper.ply, min then max); the expected rays were printed by
    // `gen_rays.py --bbox-bits bdc1ecc7 3d071dcc bd7d6f2c 3d79e4ae 3e3fd114 3d70d7f4 -n 3`.
    const BUNNY_BBOX: [u32; 6] = [0xbdc1ecc7, 0x3d071dcc, 0xbd7d6f2c, 0x3d79e4ae, 0x3e3fd114, 0x3d70d7f4];

    #[test]
    fn frame_keeps_exact_f32_bounds() {
        let f = Frame::new(&[Vec3::new(1.0, -2.0, 0.5), Vec3::new(-1.0, 3.0, 0.25), Vec3::new(0.0, 0.0, 4.0)]).unwrap();
        assert_eq!(f.bmin, [-1.0, -2.0, 0.25]);
        assert_eq!(f.bmax, [1.0, 3.0, 4.0]);
        assert_eq!(f.c, [0.0, 0.5, 2.125]);
        assert_eq!(f.e, [2.0, 5.0, 3.75]);
        assert_eq!(f.diag, (4.0f64 + 25.0 + 14.0625).sqrt());
        assert!(Frame::new(&[]).is_none());
    }

    #[test]
    fn splitmix64_matches_the_reference_stream() {
        // The first outputs of splitmix64 seeded with 1, as gen_rays.py's
        // SplitMix64 gives them.
        let mut rng = SplitMix64::new(1);
        assert_eq!(rng.next_u64(), 0x910a2dec89025cc1);
        assert_eq!(rng.next_u64(), 0xbeeb8da1658eec67);
        let mut rng = SplitMix64::new(1);
        assert_eq!(rng.uniform(), f64::from((0x910a2dec89025cc1u64 >> 40) as u32) / 16_777_216.0);
    }

    #[test]
    fn primary_rays_match_gen_rays_py() {
        let f = frame_from_bits(BUNNY_BBOX);
        let rays = primary_rays(&f);
        assert_eq!(rays.len(), NUM_PRIMARY);
        let expected = [
            [0xbc89f4e0, 0x3de19887, 0x3e7ead99, 0xbeb6dbf2, 0x3eb6dbf2, 0xbf5cf240, 0x00000000, 0x7f800000],
            [0xbc89f4e0, 0x3de19887, 0x3e7ead99, 0xbeb68c12, 0x3eb6e79c, 0xbf5d0059, 0x00000000, 0x7f800000],
            [0xbc89f4e0, 0x3de19887, 0x3e7ead99, 0xbeb63c22, 0x3eb6f343, 0xbf5d0e6d, 0x00000000, 0x7f800000],
        ];
        for (k, want) in expected.iter().enumerate() {
            assert_eq!(bits(&rays[k]), *want, "primary ray {k}");
        }
    }

    #[test]
    fn incoherent_rays_match_gen_rays_py() {
        let f = frame_from_bits(BUNNY_BBOX);
        let rays = incoherent_rays(&f);
        assert_eq!(rays.len(), NUM_INCOHERENT);
        let expected = [
            [0xbbd43ba4, 0x3e17a402, 0x3d6282c7, 0xbf6ef7fe, 0x3eae9113, 0x3de3e7a0, 0x00000000, 0x7f800000],
            [0x3cc55c8f, 0x3e2c6ee5, 0x3aa3665b, 0x3e7c7591, 0xbf5e77e8, 0x3edba3a0, 0x00000000, 0x7f800000],
            [0xbd021c68, 0x3e017552, 0xbbe48c68, 0xbf6b2184, 0x3ec81f6d, 0xbd766820, 0x00000000, 0x7f800000],
        ];
        for (i, want) in expected.iter().enumerate() {
            assert_eq!(bits(&rays[i]), *want, "incoherent ray {i}");
        }
    }

    #[test]
    fn shadow_rays_start_at_the_hits_in_primary_order() {
        let f = frame_from_bits(BUNNY_BBOX);
        let primary = primary_rays(&f);
        let mut t = vec![f32::INFINITY; primary.len()];
        t[5] = 0.25;
        t[700_000] = 0.2;
        let (rays, source) = shadow_rays(&f, &primary, &t);
        assert_eq!(source, [5, 700_000]);
        // From gen_rays.py's shadow_ray(frame, k, t).
        let expected = [
            [0xbdd7c931, 0x3e4c5754, 0x3d05d424, 0x3f68d1e8, 0x3e1bb9c5, 0x3ec624c1, 0x37d1ebee, 0x3e708e57],
            [0xbaba35e4, 0x3da978f5, 0x3d51b356, 0x3f0b7b8e, 0x3f41ee54, 0x3eb81485, 0x37d1ebee, 0x3e4e2d39],
        ];
        assert_eq!(rays.iter().map(bits).collect::<Vec<_>>(), expected);
    }
}
