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

/// Reads any numeric `.npy` array (booleans, integers of 1 to 8 bytes, floats of
/// 2, 4 or 8 bytes, either byte order, C or Fortran order) as f64 in C order,
/// with its shape. A header whose shape overflows or promises more data than the
/// file holds is refused.
pub fn read_npy(path: &Path) -> Result<(Vec<u64>, Vec<f64>), NpyError> {
    let bad = |m: String| NpyError {
        path: path.to_path_buf(),
        message: m,
    };
    let bytes = std::fs::read(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let mut cursor = std::io::Cursor::new(&bytes[..]);
    let header = npyz::NpyHeader::from_reader(&mut cursor)
        .map_err(|e| bad(format!("not a .npy file: {e}")))?;
    let data_bytes = bytes.len() - cursor.position() as usize;
    let shape = header.shape().to_vec();
    let npyz::DType::Plain(ts) = header.dtype() else {
        return Err(bad(format!(
            "unsupported dtype {:?} (need a plain numeric array)",
            header.dtype()
        )));
    };
    let count = shape
        .iter()
        .try_fold(1u64, |n, &d| n.checked_mul(d))
        .ok_or_else(|| {
            bad(format!(
                "its shape {shape:?} has more elements than can exist"
            ))
        })?;
    let needed = count.checked_mul(ts.size_field());
    if needed.is_none_or(|n| n > data_bytes as u64) {
        return Err(bad(format!(
            "its header promises {count} elements of {} bytes (shape {shape:?}) but the file holds {data_bytes} bytes of data: truncated or corrupt",
            ts.size_field()
        )));
    }
    let order = header.order();
    let npy = npyz::NpyFile::with_header(header, &bytes[cursor.position() as usize..]);
    use npyz::TypeChar as T;
    let data: std::io::Result<Vec<f64>> = match (ts.type_char(), ts.size_field()) {
        (T::Float, 8) => npy.into_vec::<f64>(),
        (T::Float, 4) => into_f64::<f32>(npy),
        (T::Float, 2) => npy
            .into_vec::<npyz::half::f16>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        (T::Int, 1) => into_f64::<i8>(npy),
        (T::Int, 2) => into_f64::<i16>(npy),
        (T::Int, 4) => into_f64::<i32>(npy),
        (T::Int, 8) => npy
            .into_vec::<i64>()
            .map(|v| v.into_iter().map(|x| x as f64).collect()),
        (T::Uint, 1) => into_f64::<u8>(npy),
        (T::Uint, 2) => into_f64::<u16>(npy),
        (T::Uint, 4) => into_f64::<u32>(npy),
        (T::Uint, 8) => npy
            .into_vec::<u64>()
            .map(|v| v.into_iter().map(|x| x as f64).collect()),
        (T::Bool, 1) => npy
            .into_vec::<bool>()
            .map(|v| v.into_iter().map(|x| f64::from(u8::from(x))).collect()),
        _ => {
            return Err(bad(format!(
                "unsupported element type {ts} (need booleans, integers of 1–8 bytes or floats of 2, 4 or 8 bytes)"
            )))
        }
    };
    let data = data.map_err(|e| bad(format!("cannot read the data: {e}")))?;
    Ok(match order {
        npyz::Order::C => (shape, data),
        npyz::Order::Fortran => {
            let c = fortran_to_c(&shape, &data);
            (shape, c)
        }
    })
}

/// All elements converted losslessly to f64.
fn into_f64<X: npyz::Deserialize + Into<f64>>(
    npy: npyz::NpyFile<&[u8]>,
) -> std::io::Result<Vec<f64>> {
    npy.into_vec::<X>()
        .map(|v| v.into_iter().map(Into::into).collect())
}

/// Elements stored in Fortran order (first index fastest) put in C order (last
/// index fastest), for any number of dimensions.
fn fortran_to_c(shape: &[u64], data: &[f64]) -> Vec<f64> {
    let dims: Vec<usize> = shape.iter().map(|&d| d as usize).collect();
    let mut index = vec![0usize; dims.len()];
    let mut out = Vec::with_capacity(data.len());
    for _ in 0..data.len() {
        // Fortran offset of the current C-order multi-index.
        let mut offset = 0;
        for k in (0..dims.len()).rev() {
            offset = offset * dims[k] + index[k];
        }
        out.push(data[offset]);
        // Next C-order multi-index: the last index runs fastest.
        for k in (0..dims.len()).rev() {
            index[k] += 1;
            if index[k] < dims[k] {
                break;
            }
            index[k] = 0;
        }
    }
    out
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
