//! Camera rays for many film positions at once: the render loop generates
//! a run's camera rays (up to 64, one a pixel) together
//! ([`Camera::generate_rays`]).
//!
//! A pinhole perspective camera, the common case, makes each ray with a
//! few products and sums, three divisions and a square root: one at a
//! time, through a call, that is mostly waiting on the divisions. Across
//! lanes, laid out structure-of-arrays, each step is one vector
//! instruction for sixteen rays. The steps are those of
//! [`Camera::generate_ray`], in the same order, and the length is applied
//! as glam's `Vec3A::normalize` applies it on the target (a division of
//! each component where its vector type is SSE2's or WebAssembly's
//! `simd128`, a product with the reciprocal elsewhere): the rays are the
//! same bits. Other cameras (thin lens, orthographic, spherical) make
//! their rays one at a time.

use super::{Camera, Model};
#[cfg(target_arch = "x86_64")]
use crate::geometry::Isa;
use crate::geometry::{isa, Ray, Vec2, Vec3};

/// Rays one kernel call makes.
const KERNEL_LANES: usize = 16;

impl Camera {
    /// [`Camera::generate_ray`] for every lane: `rays[i]` through film
    /// position `film[i]` with lens sample `lens[i]` (ignored by cameras
    /// without a lens, for which `lens` may be shorter or empty). The same
    /// rays, bit for bit, as one by one; a pinhole camera makes them
    /// sixteen at a time in vector code.
    ///
    /// # Panics
    /// If `rays` and `film` differ in length, or the camera has a lens and
    /// `lens` is shorter than `film`.
    ///
    /// ```
    /// use lucent::camera::Camera;
    /// use lucent::geometry::{Ray, Vec2, Vec3};
    ///
    /// let camera = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 64, 48).unwrap();
    /// let film = [Vec2::new(0.5, 0.5), Vec2::new(32.0, 24.0)];
    /// let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); 2];
    /// camera.generate_rays(&film, &[], &mut rays);
    /// assert!((rays[1].dir - Vec3::Z).length() < 1e-6);
    /// ```
    pub fn generate_rays(&self, film: &[Vec2], lens: &[Vec2], rays: &mut [Ray]) {
        assert_eq!(film.len(), rays.len(), "one film position a ray");
        if self.lens.is_some() {
            assert!(lens.len() >= film.len(), "a camera with a lens needs a lens sample a ray");
        }
        if !matches!((self.model, self.lens), (Model::Perspective, None)) {
            for (i, (ray, &film)) in rays.iter_mut().zip(film).enumerate() {
                let lens = if self.lens.is_some() { lens[i] } else { Vec2::ZERO };
                *ray = self.generate_ray(film, lens);
            }
            return;
        }
        for (film, rays) in film.chunks(KERNEL_LANES).zip(rays.chunks_mut(KERNEL_LANES)) {
            let mut input = FilmLanes::default();
            for (k, f) in film.iter().enumerate() {
                input.x[k] = f.x;
                input.y[k] = f.y;
            }
            let dirs = pinhole_directions(self, &input);
            for (k, ray) in rays.iter_mut().enumerate() {
                *ray = Ray::new(self.eye, Vec3::new(dirs[0][k], dirs[1][k], dirs[2][k]));
            }
        }
    }
}

/// Film positions, structure-of-arrays (unused lanes hold zeros).
#[derive(Clone, Copy, Default)]
struct FilmLanes {
    x: [f32; KERNEL_LANES],
    y: [f32; KERNEL_LANES],
}

/// Unit ray directions, one array a coordinate.
type Directions = [[f32; KERNEL_LANES]; 3];

/// [`pinhole_directions_portable`] in the best build the CPU runs.
#[inline]
fn pinhole_directions(camera: &Camera, film: &FilmLanes) -> Directions {
    match isa() {
        // SAFETY: `isa` found the features of `Isa::Avx512`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { pinhole_directions_avx512(camera, film) },
        // SAFETY: `isa` found the features of `Isa::Avx2`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { pinhole_directions_avx2(camera, film) },
        _ => pinhole_directions_portable(camera, film),
    }
}

/// [`pinhole_directions_portable`] compiled for AVX2 (eight lanes a step).
///
/// # Safety
/// The CPU must have the features of `Isa::Avx2`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn pinhole_directions_avx2(camera: &Camera, film: &FilmLanes) -> Directions {
    pinhole_directions_portable(camera, film)
}

/// [`pinhole_directions_portable`] compiled for AVX-512 (sixteen lanes a
/// step).
///
/// # Safety
/// The CPU must have the features of `Isa::Avx512`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn pinhole_directions_avx512(camera: &Camera, film: &FilmLanes) -> Directions {
    pinhole_directions_portable(camera, film)
}

/// The pinhole's ray directions: the screen-window point
/// ([`Camera::screen_xy`]), its direction `w + s_x u + s_y v`
/// ([`Camera::image_plane_direction`]), scaled to unit length as
/// `Vec3A::normalize` does; each step a loop over the lanes, with the
/// scalar code's operations in its order (no fused multiply-adds: Rust
/// does not contract `a * b + c`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // each lane index reads and writes five arrays in step
fn pinhole_directions_portable(camera: &Camera, film: &FilmLanes) -> Directions {
    let (u, v, w) = (camera.u, camera.v, camera.w);
    let mut d: Directions = [[0.0; KERNEL_LANES]; 3];
    for k in 0..KERNEL_LANES {
        let (sx, sy) = camera.screen_xy(film.x[k], film.y[k]);
        d[0][k] = w.x + sx * u.x + sy * v.x;
        d[1][k] = w.y + sx * u.y + sy * v.y;
        d[2][k] = w.z + sx * u.z + sy * v.z;
    }
    for k in 0..KERNEL_LANES {
        // `Vec3A`'s dot product: (x² + y²) + z².
        let len = (d[0][k] * d[0][k] + d[1][k] * d[1][k] + d[2][k] * d[2][k]).sqrt();
        // glam's SSE2 and simd128 `normalize` divides by the length; its
        // other backends (NEON, scalar) multiply by the reciprocal.
        if cfg!(any(target_feature = "sse2", target_feature = "simd128")) {
            d[0][k] /= len;
            d[1][k] /= len;
            d[2][k] /= len;
        } else {
            let r = 1.0 / len;
            d[0][k] *= r;
            d[1][k] *= r;
            d[2][k] *= r;
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Projection, ThinLens};
    use crate::geometry::Transform;
    use crate::sampling::Pcg32;

    /// Film positions over the whole image and beyond its edges (a
    /// filter's footprint reaches past them), in runs of awkward lengths.
    fn film_positions(rng: &mut Pcg32, n: usize, width: f32, height: f32) -> Vec<Vec2> {
        (0..n).map(|_| Vec2::new(rng.uniform() * (width + 4.0) - 2.0, rng.uniform() * (height + 4.0) - 2.0)).collect()
    }

    fn cameras() -> Vec<Camera> {
        let look = Camera::new(Vec3::new(0.3, 2.6, 9.5), Vec3::new(0.0, 0.7, 0.0), Vec3::Y, 45.0, 400, 225).unwrap();
        let wide = Camera::new(Vec3::new(-1.0, 0.5, 2.0), Vec3::new(3.0, -1.0, -7.0), Vec3::Y, 170.0, 97, 61).unwrap();
        let to_world = Transform::translate(Vec3::new(0.0, 1.0, 6.8)).then(&Transform::rotate_y(170.0));
        let window = Camera::pbrt(
            &to_world,
            Projection::Perspective {
                fov_degrees: 19.5,
                screen_window: Some([-0.7, 1.1, -0.5, 0.8]),
                frame_aspect_ratio: None,
                lens: None,
            },
            128,
            96,
        )
        .unwrap();
        let lens = look.clone().with_lens(ThinLens { radius: 0.2, focal_distance: 9.0 }).unwrap();
        let ortho = Camera::pbrt(
            &to_world,
            Projection::Orthographic { screen_window: None, frame_aspect_ratio: None, lens: None },
            64,
            64,
        )
        .unwrap();
        vec![look, wide, window, lens, ortho]
    }

    /// Every camera's rays equal `generate_ray`'s, lane by lane, bit for
    /// bit.
    #[test]
    fn rays_equal_one_by_one() {
        let mut rng = Pcg32::new(17, 3);
        for camera in cameras() {
            for n in [1, 7, 16, 33, 64] {
                let film = film_positions(&mut rng, n, camera.width() as f32, camera.height() as f32);
                let lens: Vec<Vec2> = (0..n).map(|_| Vec2::new(rng.uniform(), rng.uniform())).collect();
                let mut rays = vec![Ray::new(Vec3::ZERO, Vec3::X); n];
                camera.generate_rays(&film, &lens, &mut rays);
                for i in 0..n {
                    let one = camera.generate_ray(film[i], lens[i]);
                    assert_eq!(rays[i].origin, one.origin, "lane {i} of {n}");
                    assert_eq!(rays[i].dir, one.dir, "lane {i} of {n}, film {:?}", film[i]);
                }
            }
        }
    }

    #[test]
    #[should_panic(expected = "a lens sample a ray")]
    fn a_lens_needs_its_samples() {
        let camera = cameras().remove(3);
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); 2];
        camera.generate_rays(&[Vec2::ZERO, Vec2::ONE], &[Vec2::ZERO], &mut rays);
    }

    /// Every build the CPU runs gives the portable build's bits.
    #[test]
    fn builds_agree() {
        let mut rng = Pcg32::new(9, 1);
        for camera in cameras().into_iter().filter(|c| matches!((c.model, c.lens), (Model::Perspective, None))) {
            for _ in 0..500 {
                let mut input = FilmLanes::default();
                for k in 0..KERNEL_LANES {
                    input.x[k] = rng.uniform() * camera.width() as f32;
                    input.y[k] = rng.uniform() * camera.height() as f32;
                }
                let portable = pinhole_directions_portable(&camera, &input);
                assert_eq!(pinhole_directions(&camera, &input), portable);
                #[cfg(target_arch = "x86_64")]
                {
                    let best = crate::geometry::simd_detected();
                    if best >= Isa::Avx2 {
                        // SAFETY: the CPU has the features of `Isa::Avx2`.
                        assert_eq!(unsafe { pinhole_directions_avx2(&camera, &input) }, portable);
                    }
                    if best == Isa::Avx512 {
                        // SAFETY: the CPU has the features of `Isa::Avx512`.
                        assert_eq!(unsafe { pinhole_directions_avx512(&camera, &input) }, portable);
                    }
                }
            }
        }
    }
}
