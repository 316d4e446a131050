//! The one seeded random generator of chrono-rs (scene jitter, packings, random test
//! problems). Reproducible on every platform: the same constructor and seed give the same
//! stream. Not cryptographic.
//!
//! [`Rng::new`] is xoshiro256** (D. Blackman and S. Vigna, "Scrambled linear pseudorandom
//! number generators", ACM Trans. Math. Softw. 47(4), 2021) seeded by splitmix64 (G.
//! Steele, D. Lea, C. Flood, "Fast splittable pseudorandom number generators", OOPSLA
//! 2014); use it for new code. Two more constructors keep the streams of existing
//! validation cases bit-identical: [`Rng::splitmix64`] (the CCP benchmark problems) and
//! [`Rng::xorshift64`] (G. Marsaglia, "Xorshift RNGs", J. Stat. Softw. 8(14), 2003; the
//! tetrahedral patch test).

/// A seeded generator; see the [module documentation](self) for the algorithms.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rng {
    state: State,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum State {
    Xoshiro([u64; 4]),
    SplitMix(u64),
    XorShift(u64),
}

/// One step of splitmix64: advance `z` by the golden-ratio increment and mix it.
fn splitmix_next(z: &mut u64) -> u64 {
    *z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut x = *z;
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

impl Rng {
    /// xoshiro256** from a 64-bit seed (any value, 0 included), its state filled by
    /// splitmix64. The default choice.
    pub fn new(seed: u64) -> Self {
        let mut z = seed;
        let s = [
            splitmix_next(&mut z),
            splitmix_next(&mut z),
            splitmix_next(&mut z),
            splitmix_next(&mut z),
        ];
        Self {
            state: State::Xoshiro(s),
        }
    }

    /// splitmix64 itself with state `seed` (any value): the stream of the CCP benchmark
    /// problems (`chrono_ccp::testing`), kept so that their numbers do not change.
    pub fn splitmix64(seed: u64) -> Self {
        Self {
            state: State::SplitMix(seed),
        }
    }

    /// Marsaglia's xorshift64 (shifts 13, 7, 17) with state `seed`, kept for the streams of
    /// existing cases. A zero seed gives zeros forever; use a nonzero one.
    pub fn xorshift64(seed: u64) -> Self {
        Self {
            state: State::XorShift(seed),
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        match &mut self.state {
            State::Xoshiro(s) => {
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
            State::SplitMix(z) => splitmix_next(z),
            State::XorShift(x) => {
                *x ^= *x << 13;
                *x ^= *x >> 7;
                *x ^= *x << 17;
                *x
            }
        }
    }

    /// Uniform in `[0, 1)` (the top 53 bits of [`next_u64`](Self::next_u64)).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[a, b)`: `a + (b - a) u`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }

    /// An integer in `[lo, hi]` (both included; `lo <= hi`), by the remainder of
    /// [`next_u64`](Self::next_u64) (bias below `2^-50` for small ranges).
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        debug_assert!(lo <= hi, "Rng::int: lo = {lo} > hi = {hi}");
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_stream_and_uniform_mean() {
        let (mut a, mut b) = (Rng::new(7), Rng::new(7));
        for _ in 0..10 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
        assert_ne!(Rng::new(8).next_u64(), Rng::new(7).next_u64());
        let mut r = Rng::new(1);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| r.uniform()).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 5e-3, "{mean}");
    }

    #[test]
    fn legacy_streams_match_their_reference_algorithms() {
        // splitmix64 from 0: the published first output.
        assert_eq!(Rng::splitmix64(0).next_u64(), 0xE220_A839_7B1D_CDAF);
        // xorshift64 by hand.
        let mut x = 1u64;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        assert_eq!(Rng::xorshift64(1).next_u64(), x);
        let mut r = Rng::xorshift64(5);
        let v: Vec<usize> = (0..100).map(|_| r.int(2, 4)).collect();
        assert!(v.iter().all(|&k| (2..=4).contains(&k)));
    }
}
