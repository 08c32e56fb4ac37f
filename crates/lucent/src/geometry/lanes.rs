//! Vectors of many lanes at once, coordinate by coordinate
//! (structure of arrays), for kernels that run one computation over many
//! paths: each step is a loop over the lanes that the compiler turns into
//! vector instructions.

use super::Vec3;

/// Lanes of a [`Vec3Lanes`]: the path integrator's batch of paths.
pub const LANES: usize = 64;

/// Up to [`LANES`] 3-vectors, each coordinate in its own array.
#[derive(Clone, Copy, Debug)]
pub struct Vec3Lanes {
    /// The x coordinates.
    pub x: [f32; LANES],
    /// The y coordinates.
    pub y: [f32; LANES],
    /// The z coordinates.
    pub z: [f32; LANES],
}

impl Vec3Lanes {
    /// Every lane zero.
    pub const ZERO: Self = Self { x: [0.0; LANES], y: [0.0; LANES], z: [0.0; LANES] };

    /// Lane `i`.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    /// Set lane `i` to `v`.
    #[inline(always)]
    pub fn set(&mut self, i: usize, v: Vec3) {
        (self.x[i], self.y[i], self.z[i]) = (v.x, v.y, v.z);
    }

    /// The dot product of lane `i` with `v`, rounded as [`Vec3::dot`]
    /// rounds it: `(x·vx + y·vy) + z·vz`.
    #[inline(always)]
    pub fn dot(&self, i: usize, v: Vec3) -> f32 {
        self.x[i] * v.x + self.y[i] * v.y + self.z[i] * v.z
    }

    /// The dot product of lane `i` of `self` and of `other`, rounded as
    /// [`Vec3::dot`] rounds it.
    #[inline(always)]
    pub fn dot_lanes(&self, other: &Self, i: usize) -> f32 {
        self.x[i] * other.x[i] + self.y[i] * other.y[i] + self.z[i] * other.z[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_trip_and_dot_as_glam_does() {
        let mut l = Vec3Lanes::ZERO;
        let (a, b) = (Vec3::new(0.1, -3.7, 1e-3), Vec3::new(7.3, 0.3, -2.9));
        l.set(5, a);
        assert_eq!(l.get(5), a);
        assert_eq!(l.dot(5, b).to_bits(), a.dot(b).to_bits());
        let mut m = Vec3Lanes::ZERO;
        m.set(5, b);
        assert_eq!(l.dot_lanes(&m, 5).to_bits(), a.dot(b).to_bits());
    }
}
