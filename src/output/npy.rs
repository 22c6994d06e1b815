//! NumPy `.npy` arrays (C order, little endian): written atomically, and read
//! back as images (any numeric type) for `traxer eef` and `traxer render`.

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

/// A `.npy` file that is not a usable image.
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct NpyError {
    pub path: std::path::PathBuf,
    pub message: String,
}

/// Reads any numeric `.npy` array as f64 with its shape.
pub fn read_npy(path: &Path) -> Result<(Vec<u64>, Vec<f64>), NpyError> {
    let bad = |m: String| NpyError {
        path: path.to_path_buf(),
        message: m,
    };
    let bytes = std::fs::read(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let npy = npyz::NpyFile::new(&bytes[..]).map_err(|e| bad(format!("not a .npy file: {e}")))?;
    let shape = npy.shape().to_vec();
    let type_str = match npy.dtype() {
        npyz::DType::Plain(t) => t.to_string(),
        other => {
            return Err(bad(format!(
                "unsupported dtype {other:?} (need a plain numeric array)"
            )))
        }
    };
    let data: Vec<f64> = match &type_str[1..] {
        "f8" => npy.into_vec::<f64>(),
        "f4" => npy
            .into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        "u8" => npy
            .into_vec::<u64>()
            .map(|v| v.into_iter().map(|x| x as f64).collect()),
        "i8" => npy
            .into_vec::<i64>()
            .map(|v| v.into_iter().map(|x| x as f64).collect()),
        "u4" => npy
            .into_vec::<u32>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        "i4" => npy
            .into_vec::<i32>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        other => {
            return Err(bad(format!(
                "unsupported element type {other} (use float or integer)"
            )))
        }
    }
    .map_err(|e| bad(format!("cannot read the data: {e}")))?;
    Ok((shape, data))
}

/// A 2-D image read from a `.npy` file, summed over bands if it has them.
#[derive(Clone, Debug)]
pub struct NpyImage {
    /// The array's shape as stored: [ny, nx] or [bands, ny, nx].
    pub shape: Vec<u64>,
    pub ny: usize,
    pub nx: usize,
    /// Row-major [iy][ix], summed over the bands.
    pub summed: Vec<f64>,
}

/// Reads a 2-D image [iy][ix] or a stack [band][iy][ix] (summed over bands) of
/// any numeric type.
pub fn read_image(path: &Path) -> Result<NpyImage, NpyError> {
    let (shape, data) = read_npy(path)?;
    let (ny, nx) = match shape[..] {
        [ny, nx] | [_, ny, nx] => (ny as usize, nx as usize),
        _ => {
            return Err(NpyError {
                path: path.to_path_buf(),
                message: format!("expected a 2-D or 3-D image, got shape {shape:?}"),
            })
        }
    };
    let summed = crate::sensor::sum_bands(&data, ny * nx);
    Ok(NpyImage {
        shape,
        ny,
        nx,
        summed,
    })
}
