//! Exact sums of photon weights: the reason a run cut into shards, traced on many
//! machines in any order and merged, gives the bit-identical image of one run.
//!
//! Floating-point addition is not associative: the same weights added in another
//! grouping (shard 1's pixel sum plus shard 2's, instead of one sum in photon
//! order) differ in the last bits. Sensors therefore add weights as integers in
//! units of 2⁻⁸⁰ (a 128-bit fixed-point number with 48 integer bits), where
//! addition is exact and any order gives the same bits; the floating-point flux
//! is made once, at the end, by one correctly rounded conversion.
//!
//! Resolution and range: a weight loses only what lies below 2⁻⁸⁰ ≈ 8·10⁻²⁵, so
//! weights down to 2⁻²⁷ ≈ 7·10⁻⁹ keep all 53 significant bits (a point source
//! 120 m away has weights near 10⁻⁷, times the mirrors' reflectivities); one pixel can hold a total weight of 2⁴⁸ ≈ 2.8·10¹⁴, which is 10¹⁴
//! photons of weight ≤ 1 (every source's weight is ≤ 1), about three years of
//! tracing at a million photons per second into a single pixel. Beyond that the
//! sum saturates rather than wrapping round.

/// Fractional bits of the fixed-point sums.
const FRACTION_BITS: i32 = 80;

/// A sum of non-negative weights, exact and independent of the order of addition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct WeightSum(u128);

impl WeightSum {
    pub const ZERO: WeightSum = WeightSum(0);

    /// One weight in fixed-point units (truncated below 2⁻⁸⁰; negative and NaN
    /// weights, which no source or material makes, count as 0).
    #[inline]
    pub fn of(weight: f64) -> WeightSum {
        // `as` saturates: negative and NaN give 0, beyond range gives u128::MAX.
        WeightSum((weight * (2f64).powi(FRACTION_BITS)) as u128)
    }

    /// Adds another sum (saturating at the largest representable sum).
    #[inline]
    pub fn add(&mut self, other: WeightSum) {
        self.0 = self.0.saturating_add(other.0);
    }

    /// The sum as a floating-point number (correctly rounded).
    #[inline]
    pub fn value(self) -> f64 {
        self.0 as f64 * (2f64).powi(-FRACTION_BITS)
    }
}

/// Adds `other` into `sums` element by element.
pub fn add_all(sums: &mut [WeightSum], other: &[WeightSum]) {
    for (s, o) in sums.iter_mut().zip(other) {
        s.add(*o);
    }
}

/// The sums as floating-point numbers.
pub fn values(sums: &[WeightSum]) -> Vec<f64> {
    sums.iter().map(|s| s.value()).collect()
}
