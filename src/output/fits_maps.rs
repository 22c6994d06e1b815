//! Maps on one linear frame as a FITS file (the systematics study's mean, nominal
//! and σ maps): the first as the primary image, the others as extensions, each
//! with the WCS in mm, its unit and what it holds; the FITS machinery is
//! `fits`'s.

use super::fits::{mm_axes, provenance_keys, write_fits, Extension, FluxUnit, Keys};
use super::Provenance;
use std::path::Path;

/// One map of [`write_maps_fits`]: its extension name (none for the first,
/// the primary) and what it is.
pub struct Map<'a> {
    pub name: String,
    pub data: &'a [f64],
    pub what: String,
}

/// Writes maps of `dims` ([ny, nx]) on one linear frame in mm (`first` pixel
/// centre, `step`; `frame` says which) as the FITS file `path`: the first as
/// the primary image, the others as extensions, each with the WCS, BUNIT and
/// a CONTENT card; the provenance keys in the primary.
pub fn write_maps_fits(
    path: &Path,
    dims: [usize; 2],
    (first, step, frame): ([f64; 2], [f64; 2], &str),
    unit: &FluxUnit,
    maps: &[Map],
    (provenance, json_name): (&Provenance, &str),
) -> std::io::Result<()> {
    let keys_of = |m: &Map| {
        let mut keys = Keys::default();
        keys.text("BUNIT", unit.bunit, unit.comment);
        keys.text("CONTENT", &m.what, "");
        mm_axes(&mut keys, first, step, frame);
        keys
    };
    let mut primary = keys_of(&maps[0]);
    provenance_keys(&mut primary, provenance, json_name);
    let extensions = maps[1..]
        .iter()
        .map(|m| Extension {
            name: m.name.clone(),
            dims: dims.to_vec(),
            data: m.data,
            keys: keys_of(m),
        })
        .collect();
    write_fits(path, &dims, maps[0].data, primary, extensions)
}
