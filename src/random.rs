//! Reproducible random numbers: photon i's stream is derived from (seed, i) alone,
//! never from thread identity, so a run gives bit-identical results for any
//! number of threads and any split into shards.

use rand_core::{RngCore, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;

/// SplitMix64 finaliser: a bijective mixer of 64-bit words.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random stream of one photon.
pub struct PhotonRng(Xoshiro256PlusPlus);

impl PhotonRng {
    /// Stream for photon `index` of a run with `seed`.
    #[inline]
    pub fn new(seed: u64, index: u64) -> PhotonRng {
        PhotonRng(Xoshiro256PlusPlus::seed_from_u64(mix(mix(seed) ^ index)))
    }

    /// Uniform in [0, 1) with 53 random bits.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A standard normal deviate, by the ziggurat method (rand_distr's
    /// `StandardNormal`): one 64-bit draw and a table lookup almost always, a
    /// logarithm or exponential only in the rare tail and wedge cases. How many
    /// draws it takes depends on the stream alone, never on what the caller does
    /// with the deviate.
    #[inline]
    pub fn normal(&mut self) -> f64 {
        StandardNormal.sample(&mut self.0)
    }
}
