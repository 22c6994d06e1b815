//! NumPy `.npy` arrays (C order, little endian), written atomically.

use crate::files::atomic_write;
use npyz::WriterBuilder;
use std::path::Path;

/// Writes an f64 array of the given shape (row-major).
pub fn write_npy_f64(path: &Path, shape: &[u64], data: &[f64]) -> std::io::Result<()> {
    write(path, shape, data)
}

/// Writes a u64 array of the given shape (row-major).
pub fn write_npy_u64(path: &Path, shape: &[u64], data: &[u64]) -> std::io::Result<()> {
    write(path, shape, data)
}

fn write<T: npyz::Serialize + npyz::AutoSerialize + Copy>(
    path: &Path,
    shape: &[u64],
    data: &[T],
) -> std::io::Result<()> {
    assert_eq!(
        shape.iter().product::<u64>() as usize,
        data.len(),
        "npy shape mismatch"
    );
    let mut buf = Vec::with_capacity(128 + data.len() * 8);
    {
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(&mut buf)
            .begin_nd()?;
        w.extend(data.iter().copied())?;
        w.finish()?;
    }
    atomic_write(path, &buf)
}
