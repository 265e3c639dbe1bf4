//! SplitMix64 (Steele, Lea & Flood 2014): a tiny, well-mixed, seedable generator for the
//! tests' random bodies and scenes, reproducible from its seed.
#![allow(dead_code)] // each test binary uses a different subset

use nalgebra::{Rotation3, Unit, Vector3};

pub struct Rng(pub u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// Uniform in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n
    }
    /// Each component uniform in [−scale, scale].
    pub fn vector(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
        ) * scale
    }
    pub fn rotation(&mut self) -> Rotation3<f64> {
        let axis = Unit::new_normalize(self.vector(1.0) + Vector3::new(1e-3, 0.0, 0.0));
        Rotation3::from_axis_angle(&axis, self.uniform(0.0, std::f64::consts::PI))
    }
}
