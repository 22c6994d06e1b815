//! `traxer eef` reads every valid `.npy`: Fortran order, every integer width,
//! float16, booleans; and refuses headers that promise more data than there is.

use crate::common::{run_fails, run_ok, traxer};
use std::path::Path;

/// A version 1.0 `.npy` file written by hand: the header dictionary padded so
/// that the data starts at a multiple of 64 bytes.
fn npy_bytes(descr: &str, fortran: bool, shape: &[u64], data: &[u8]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut dict = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
        if fortran { "True" } else { "False" }
    );
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((dict.len() as u16).to_le_bytes());
    out.extend(dict.as_bytes());
    out.extend(data);
    out
}

/// The test image: 4 rows × 6 columns, zero but for 5 at (row 1, column 4) and
/// 1 at (row 3, column 0): asymmetric, so a transposed or reordered read moves
/// the centroid.
const NY: usize = 4;
const NX: usize = 6;
fn image() -> Vec<f64> {
    let mut v = vec![0.0; NY * NX];
    v[NX + 4] = 5.0;
    v[3 * NX] = 1.0;
    v
}

/// The image's values in C order, or Fortran order (column by column).
fn ordered(fortran: bool) -> Vec<f64> {
    let v = image();
    if !fortran {
        return v;
    }
    let mut f = Vec::with_capacity(v.len());
    for ix in 0..NX {
        for iy in 0..NY {
            f.push(v[iy * NX + ix]);
        }
    }
    f
}

/// `traxer eef --json` centroid of a file.
fn centroid(path: &Path) -> (f64, f64) {
    let out = run_ok(
        traxer()
            .arg("eef")
            .arg(path)
            .args(["--json", "--pixel-pitch", "1"]),
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let c = &v["centroid_mm"];
    (c[0].as_f64().unwrap(), c[1].as_f64().unwrap())
}

#[test]
fn every_numeric_npy_gives_the_same_centroid() {
    let dir = tempfile::tempdir().unwrap();
    let shape = [NY as u64, NX as u64];
    let reference = {
        let p = dir.path().join("f8.npy");
        let data: Vec<u8> = image().iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&p, npy_bytes("<f8", false, &shape, &data)).unwrap();
        centroid(&p)
    };
    // Expected from the pixel centres: x = (5·4.5 + 1·0.5)/6, y = (5·1.5 + 1·3.5)/6,
    // about the image centre (3, 2).
    let want = ((5.0 * 4.5 + 0.5) / 6.0 - 3.0, (5.0 * 1.5 + 3.5) / 6.0 - 2.0);
    assert!(
        (reference.0 - want.0).abs() < 1e-12 && (reference.1 - want.1).abs() < 1e-12,
        "{reference:?} vs {want:?}"
    );
    type Encode = fn(f64) -> Vec<u8>;
    let encodings: [(&str, Encode); 11] = [
        ("<f4", |v| (v as f32).to_le_bytes().to_vec()),
        (">f4", |v| (v as f32).to_be_bytes().to_vec()),
        ("<f2", |v| {
            npyz::half::f16::from_f64(v).to_le_bytes().to_vec()
        }),
        ("|i1", |v| (v as i8).to_le_bytes().to_vec()),
        ("|u1", |v| (v as u8).to_le_bytes().to_vec()),
        ("<i2", |v| (v as i16).to_le_bytes().to_vec()),
        ("<u2", |v| (v as u16).to_le_bytes().to_vec()),
        ("<i4", |v| (v as i32).to_le_bytes().to_vec()),
        ("<u4", |v| (v as u32).to_le_bytes().to_vec()),
        ("<i8", |v| (v as i64).to_le_bytes().to_vec()),
        ("<u8", |v| (v as u64).to_le_bytes().to_vec()),
    ];
    for fortran in [false, true] {
        for (descr, encode) in encodings {
            let data: Vec<u8> = ordered(fortran).into_iter().flat_map(encode).collect();
            let p = dir
                .path()
                .join(format!("img_{}_{fortran}.npy", &descr[1..]));
            std::fs::write(&p, npy_bytes(descr, fortran, &shape, &data)).unwrap();
            let c = centroid(&p);
            assert!(
                (c.0 - reference.0).abs() < 1e-12 && (c.1 - reference.1).abs() < 1e-12,
                "{descr}, fortran {fortran}: {c:?} vs {reference:?}"
            );
        }
    }
    // A Fortran-order stack [band][iy][ix] is summed over bands like a C one.
    let stack: Vec<f64> = [image(), image()].concat();
    let mut f = Vec::new();
    for ix in 0..NX {
        for iy in 0..NY {
            for b in 0..2 {
                f.push(stack[b * NY * NX + iy * NX + ix]);
            }
        }
    }
    let p = dir.path().join("stack_f.npy");
    let data: Vec<u8> = f.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(
        &p,
        npy_bytes("<f8", true, &[2, NY as u64, NX as u64], &data),
    )
    .unwrap();
    let c = centroid(&p);
    assert!((c.0 - reference.0).abs() < 1e-12 && (c.1 - reference.1).abs() < 1e-12);
}

#[test]
fn a_header_promising_more_than_the_file_holds_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // 2^33 × 2^33 elements: the product overflows 64 bits (and wrapped to 0).
    let p = dir.path().join("huge.npy");
    std::fs::write(&p, npy_bytes("<f8", false, &[1 << 33, 1 << 33], &[0; 16])).unwrap();
    let err = run_fails(traxer().arg("eef").arg(&p).args(["--pixel-pitch", "1"]), 2);
    assert!(err.contains("shape"), "{err}");
    // A shape larger than the data.
    let p = dir.path().join("short.npy");
    std::fs::write(&p, npy_bytes("<f8", false, &[100, 100], &[0; 64])).unwrap();
    let err = run_fails(traxer().arg("eef").arg(&p).args(["--pixel-pitch", "1"]), 2);
    assert!(err.contains("truncated"), "{err}");
}
