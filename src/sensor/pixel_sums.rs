//! Per-pixel sums stored in blocks that exist only where photons landed: a
//! sensor's memory follows the illuminated area, not the pixel count. A
//! telescope focuses its beam onto a few thousand of a 2000 × 2000 sensor's four
//! million pixels, whose dense flux and counts (24 bytes a pixel) took 96 MB,
//! twice that while `traxer merge` added two shards.
//!
//! Data flow: [`super::SensorImage`] records each photon into its flux and count
//! [`PixelSums`]; `output` reads them back as dense images. They encode (serde)
//! exactly as the dense `Vec` they replace, so run-state files are unchanged.

use serde::de::{Deserialize, Deserializer};
use serde::ser::{Serialize, Serializer};

/// Pixels per block (a power of two: the block is the index's high bits). 4096
/// consecutive pixels are two rows of a 2000-wide sensor; a focused spot touches
/// a few dozen blocks.
const BLOCK_BITS: u32 = 12;
const BLOCK: usize = 1 << BLOCK_BITS;

/// `len` values of `T`, all `T::default()` (zero) until first added to.
#[derive(Clone)]
pub struct PixelSums<T> {
    len: usize,
    blocks: Vec<Option<Box<[T]>>>,
}

impl<T: Copy + Default + PartialEq> PixelSums<T> {
    /// `len` zeros (no block allocated).
    pub fn new(len: usize) -> PixelSums<T> {
        PixelSums {
            len,
            blocks: vec![None; len.div_ceil(BLOCK)],
        }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The value at `i` (zero where nothing was added).
    #[inline]
    pub fn get(&self, i: usize) -> T {
        assert!(i < self.len, "pixel {i} of {}", self.len);
        match &self.blocks[i >> BLOCK_BITS] {
            Some(block) => block[i & (BLOCK - 1)],
            None => T::default(),
        }
    }

    /// The value at `i`, its block allocated on first use.
    #[inline]
    pub fn get_mut(&mut self, i: usize) -> &mut T {
        assert!(i < self.len, "pixel {i} of {}", self.len);
        let b = i >> BLOCK_BITS;
        let size = BLOCK.min(self.len - (b << BLOCK_BITS));
        let block = self.blocks[b].get_or_insert_with(|| vec![T::default(); size].into());
        &mut block[i & (BLOCK - 1)]
    }

    /// Every value in pixel order, zeros included.
    pub fn iter(&self) -> impl Iterator<Item = T> + '_ {
        (0..self.len).map(|i| self.get(i))
    }

    /// The values present: (pixel, value) for each pixel of an allocated block.
    pub fn allocated(&self) -> impl Iterator<Item = (usize, T)> + '_ {
        self.blocks.iter().enumerate().flat_map(|(b, block)| {
            block.iter().flat_map(move |v| {
                v.iter()
                    .enumerate()
                    .map(move |(k, &x)| ((b << BLOCK_BITS) + k, x))
            })
        })
    }

    /// The dense image.
    pub fn to_vec(&self) -> Vec<T> {
        self.iter().collect()
    }

    /// From a dense image (all-zero blocks left out).
    pub fn from_dense(values: &[T]) -> PixelSums<T> {
        let mut sums = PixelSums::new(values.len());
        for (b, chunk) in values.chunks(BLOCK).enumerate() {
            if chunk.iter().any(|v| *v != T::default()) {
                sums.blocks[b] = Some(chunk.into());
            }
        }
        sums
    }

    /// Adds `other` (of the same length) value by value with `add`.
    pub fn add_with(&mut self, other: &PixelSums<T>, add: impl Fn(&mut T, T)) {
        assert_eq!(self.len, other.len, "adding images of different sizes");
        for (b, theirs) in other.blocks.iter().enumerate() {
            let Some(theirs) = theirs else { continue };
            match &mut self.blocks[b] {
                Some(ours) => ours
                    .iter_mut()
                    .zip(theirs.iter())
                    .for_each(|(a, &x)| add(a, x)),
                empty => *empty = Some(theirs.clone()),
            }
        }
    }
}

impl<T: Copy + Default + PartialEq> PartialEq for PixelSums<T> {
    /// Equal values, wherever blocks happen to be allocated.
    fn eq(&self, other: &PixelSums<T>) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl<T: Copy + Default + PartialEq> std::fmt::Debug for PixelSums<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let used = self.blocks.iter().filter(|b| b.is_some()).count();
        write!(
            f,
            "PixelSums({} pixels, {used} of {} blocks)",
            self.len,
            self.blocks.len()
        )
    }
}

impl<T: Copy + Default + PartialEq + Serialize> Serialize for PixelSums<T> {
    /// As the dense sequence (a `Vec<T>`'s encoding, streamed).
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl<'de, T: Copy + Default + PartialEq + Deserialize<'de>> Deserialize<'de> for PixelSums<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<PixelSums<T>, D::Error> {
        Vec::<T>::deserialize(deserializer).map(|v| PixelSums::from_dense(&v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_what_a_dense_image_holds() {
        // A length that is not a whole number of blocks, values in the last one.
        let n = 3 * BLOCK + 17;
        let mut dense = vec![0u64; n];
        let mut sums = PixelSums::new(n);
        for (k, i) in [5, BLOCK + 3, 3 * BLOCK + 16, 5, 2 * BLOCK]
            .into_iter()
            .enumerate()
        {
            dense[i] += k as u64 + 1;
            *sums.get_mut(i) += k as u64 + 1;
        }
        assert_eq!(sums.to_vec(), dense);
        assert_eq!(sums.get(3 * BLOCK + 16), 3);
        assert_eq!(PixelSums::from_dense(&dense), sums);
        let allocated: Vec<_> = sums.allocated().filter(|(_, v)| *v != 0).collect();
        assert_eq!(
            allocated,
            vec![(5, 5), (BLOCK + 3, 2), (2 * BLOCK, 5), (3 * BLOCK + 16, 3)]
        );

        // Adding images: blocks only one side has, and blocks both have.
        let mut other = PixelSums::new(n);
        *other.get_mut(6) += 10;
        *other.get_mut(3 * BLOCK) += 7;
        let mut total = sums.clone();
        total.add_with(&other, |a, b| *a += b);
        let expected: Vec<u64> = dense
            .iter()
            .zip(other.to_vec())
            .map(|(a, b)| a + b)
            .collect();
        assert_eq!(total.to_vec(), expected);

        // Encodes as the dense Vec it replaces (run-state files unchanged).
        let bytes = postcard::to_allocvec(&sums).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&dense).unwrap());
        let back: PixelSums<u64> = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(back, sums);
    }
}
