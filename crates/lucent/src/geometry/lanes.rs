//! Vectors of many lanes at once, coordinate by coordinate
//! (structure of arrays), for kernels that run one computation over many
//! paths: each step is a loop over the lanes that the compiler turns into
//! vector instructions.

use super::Vec3;

/// Lanes of a [`Vec3Lanes`]: the path integrator's batch of paths.
pub const LANES: usize = 64;

/// Lanes of one AVX2 register: kernels that run over [`LANES`] lanes
/// take them in groups of this many, so that each group is one vector
/// per value and no lane is left to a scalar remainder loop (the lanes of
/// the last group past the count are computed on whatever they hold, and
/// not used).
pub const GROUP: usize = 8;

/// The group of lanes `c..c + GROUP` of `a` (`c` a multiple of [`GROUP`]).
#[inline(always)]
pub fn group<T: Copy + Default>(a: &[T; LANES], c: usize) -> [T; GROUP] {
    let mut g = [T::default(); GROUP];
    g.copy_from_slice(&a[c..c + GROUP]);
    g
}

/// Set the group of lanes `c..c + GROUP` of `a` to `g`.
#[inline(always)]
pub fn set_group<T: Copy>(a: &mut [T; LANES], c: usize, g: [T; GROUP]) {
    a[c..c + GROUP].copy_from_slice(&g);
}

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

    /// The group of lanes `c..c + GROUP`, coordinate by coordinate.
    #[inline(always)]
    pub fn group(&self, c: usize) -> [[f32; GROUP]; 3] {
        [group(&self.x, c), group(&self.y, c), group(&self.z, c)]
    }

    /// Set the group of lanes `c..c + GROUP` to `g`.
    #[inline(always)]
    pub fn set_group(&mut self, c: usize, g: [[f32; GROUP]; 3]) {
        set_group(&mut self.x, c, g[0]);
        set_group(&mut self.y, c, g[1]);
        set_group(&mut self.z, c, g[2]);
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
