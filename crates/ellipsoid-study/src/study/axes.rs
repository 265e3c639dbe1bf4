//! The values an axis takes: evenly or geometrically spaced, uniformly random, or a Latin
//! hypercube over several keys. Random values come from a generator defined here
//! (xoshiro256** seeded through SplitMix64, Blackman & Vigna 2018), not from a crate whose
//! stream may change between versions: a seed gives the same points on every machine and
//! in every release.

/// `n` values from `start` to `stop` inclusive, evenly spaced (`start + (stop − start)·i/(n − 1)`,
/// the last exactly `stop`; one value is `start`).
pub fn linspace(start: f64, stop: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            if n == 1 {
                start
            } else if i + 1 == n {
                stop
            } else {
                start + (stop - start) * (i as f64 / (n - 1) as f64)
            }
        })
        .collect()
}

/// `n` values from `start` to `stop` inclusive (both > 0), geometrically spaced: the
/// values themselves are the ends, not their exponents (numpy's `geomspace`, not
/// `logspace`). The ends are exact.
pub fn logspace(start: f64, stop: f64, n: usize) -> Vec<f64> {
    let (a, b) = (start.ln(), stop.ln());
    (0..n)
        .map(|i| {
            if i == 0 {
                start
            } else if i + 1 == n {
                stop
            } else {
                (a + (b - a) * (i as f64 / (n - 1) as f64)).exp()
            }
        })
        .collect()
}

/// `n` values drawn uniformly from [low, high).
pub fn random(low: f64, high: f64, n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| low + (high - low) * rng.unit()).collect()
}

/// A Latin hypercube of `n` points over the boxes [low_k, high_k): each dimension is cut
/// into `n` equal strata and every stratum holds exactly one point (McKay, Beckman &
/// Conover 1979); strata are matched across dimensions by independent random
/// permutations and each point lies uniformly inside its stratum. Returns one `Vec` per
/// dimension (each of length `n`).
pub fn latin_hypercube(low: &[f64], high: &[f64], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Rng::new(seed);
    low.iter()
        .zip(high)
        .map(|(&lo, &hi)| {
            let mut strata: Vec<usize> = (0..n).collect();
            // Fisher–Yates.
            for i in (1..n).rev() {
                let j = rng.below(i as u64 + 1) as usize;
                strata.swap(i, j);
            }
            strata
                .iter()
                .map(|&s| lo + (hi - lo) * ((s as f64 + rng.unit()) / n as f64))
                .collect()
        })
        .collect()
}

/// xoshiro256** (Blackman & Vigna, "Scrambled linear pseudorandom number generators",
/// 2018), its state filled by SplitMix64 from the seed as the authors recommend.
pub struct Rng([u64; 4]);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        Rng([next(), next(), next(), next()])
    }

    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.0;
        let result = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform in [0, 1): the top 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in 0..n (n > 0), without modulo bias (Lemire's multiply-and-reject).
    pub fn below(&mut self, n: u64) -> u64 {
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = u128::from(self.next_u64()) * u128::from(n);
            if (m as u64) >= threshold {
                return (m >> 64) as u64;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_hits_both_ends_exactly() {
        let v = linspace(0.1, 0.7, 7);
        assert_eq!(v.len(), 7);
        assert_eq!((v[0], v[6]), (0.1, 0.7));
        assert!((v[3] - 0.4).abs() < 1e-15);
        assert_eq!(linspace(2.0, 3.0, 1), vec![2.0]);
        let g = logspace(1e-3, 1e-1, 5);
        assert_eq!((g[0], g[4]), (1e-3, 1e-1));
        assert!((g[2] - 1e-2).abs() < 1e-16, "{g:?}");
    }

    #[test]
    fn the_generator_is_the_published_xoshiro256starstar() {
        // Reference: the authors' C code seeded with state {1, 2, 3, 4}.
        let mut r = Rng([1, 2, 3, 4]);
        let first: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(first, vec![11520, 0, 1509978240]);
        // SplitMix64(0)'s first output (Vigna's splitmix64.c).
        assert_eq!(Rng::new(0).0[0], 0xe220_a839_7b1d_cdaf);
    }

    #[test]
    fn a_latin_hypercube_puts_one_point_in_every_stratum() {
        let n = 50;
        let pts = latin_hypercube(&[0.0, 10.0], &[1.0, 20.0], n, 7);
        for (d, (lo, hi)) in pts.iter().zip([(0.0, 1.0), (10.0, 20.0)]) {
            let mut seen = vec![false; n];
            for &x in d {
                assert!((lo..hi).contains(&x));
                let s = ((x - lo) / (hi - lo) * n as f64) as usize;
                assert!(!seen[s], "two points in stratum {s}");
                seen[s] = true;
            }
        }
        assert_eq!(pts, latin_hypercube(&[0.0, 10.0], &[1.0, 20.0], n, 7));
        assert_ne!(pts, latin_hypercube(&[0.0, 10.0], &[1.0, 20.0], n, 8));
    }

    #[test]
    fn random_values_are_reproducible_and_in_range() {
        let v = random(-1.0, 2.0, 1000, 42);
        assert!(v.iter().all(|x| (-1.0..2.0).contains(x)));
        assert_eq!(v, random(-1.0, 2.0, 1000, 42));
        let mean = v.iter().sum::<f64>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.1, "{mean}");
    }
}
