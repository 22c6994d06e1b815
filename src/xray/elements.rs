//! Elements: standard atomic weights and two tables of atomic scattering factors
//! (f1, f2 versus energy): Henke / CXRO, the default, and Chantler / NIST FFAST,
//! the second opinion a mirror's reflectivity model can be checked against; all
//! compiled in from `data/` (see data/README.md).
//!
//! Data flow: `compound` resolves the symbols of a chemical formula here;
//! `optical` interpolates f1 and f2 at a photon energy.

use std::sync::OnceLock;

/// Lowest and highest energy (keV) the Henke tables cover.
pub const HENKE_MIN_KEV: f64 = 0.030;
pub const HENKE_MAX_KEV: f64 = 30.0;

macro_rules! henke {
    ($s:literal) => {
        include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/data/henke/",
            $s,
            ".nff"
        ))
    };
}

/// The `.nff` files in order of Z (index Z − 1).
const HENKE_FILES: [&str; 92] = [
    henke!("h"),
    henke!("he"),
    henke!("li"),
    henke!("be"),
    henke!("b"),
    henke!("c"),
    henke!("n"),
    henke!("o"),
    henke!("f"),
    henke!("ne"),
    henke!("na"),
    henke!("mg"),
    henke!("al"),
    henke!("si"),
    henke!("p"),
    henke!("s"),
    henke!("cl"),
    henke!("ar"),
    henke!("k"),
    henke!("ca"),
    henke!("sc"),
    henke!("ti"),
    henke!("v"),
    henke!("cr"),
    henke!("mn"),
    henke!("fe"),
    henke!("co"),
    henke!("ni"),
    henke!("cu"),
    henke!("zn"),
    henke!("ga"),
    henke!("ge"),
    henke!("as"),
    henke!("se"),
    henke!("br"),
    henke!("kr"),
    henke!("rb"),
    henke!("sr"),
    henke!("y"),
    henke!("zr"),
    henke!("nb"),
    henke!("mo"),
    henke!("tc"),
    henke!("ru"),
    henke!("rh"),
    henke!("pd"),
    henke!("ag"),
    henke!("cd"),
    henke!("in"),
    henke!("sn"),
    henke!("sb"),
    henke!("te"),
    henke!("i"),
    henke!("xe"),
    henke!("cs"),
    henke!("ba"),
    henke!("la"),
    henke!("ce"),
    henke!("pr"),
    henke!("nd"),
    henke!("pm"),
    henke!("sm"),
    henke!("eu"),
    henke!("gd"),
    henke!("tb"),
    henke!("dy"),
    henke!("ho"),
    henke!("er"),
    henke!("tm"),
    henke!("yb"),
    henke!("lu"),
    henke!("hf"),
    henke!("ta"),
    henke!("w"),
    henke!("re"),
    henke!("os"),
    henke!("ir"),
    henke!("pt"),
    henke!("au"),
    henke!("hg"),
    henke!("tl"),
    henke!("pb"),
    henke!("bi"),
    henke!("po"),
    henke!("at"),
    henke!("rn"),
    henke!("fr"),
    henke!("ra"),
    henke!("ac"),
    henke!("th"),
    henke!("pa"),
    henke!("u"),
];

macro_rules! chantler {
    ($s:literal) => {
        include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/data/chantler/",
            $s,
            ".nff"
        ))
    };
}

/// Chantler's tables in the same layout (scripts/make_chantler_tables.py).
const CHANTLER_FILES: [&str; 92] = [
    chantler!("h"),
    chantler!("he"),
    chantler!("li"),
    chantler!("be"),
    chantler!("b"),
    chantler!("c"),
    chantler!("n"),
    chantler!("o"),
    chantler!("f"),
    chantler!("ne"),
    chantler!("na"),
    chantler!("mg"),
    chantler!("al"),
    chantler!("si"),
    chantler!("p"),
    chantler!("s"),
    chantler!("cl"),
    chantler!("ar"),
    chantler!("k"),
    chantler!("ca"),
    chantler!("sc"),
    chantler!("ti"),
    chantler!("v"),
    chantler!("cr"),
    chantler!("mn"),
    chantler!("fe"),
    chantler!("co"),
    chantler!("ni"),
    chantler!("cu"),
    chantler!("zn"),
    chantler!("ga"),
    chantler!("ge"),
    chantler!("as"),
    chantler!("se"),
    chantler!("br"),
    chantler!("kr"),
    chantler!("rb"),
    chantler!("sr"),
    chantler!("y"),
    chantler!("zr"),
    chantler!("nb"),
    chantler!("mo"),
    chantler!("tc"),
    chantler!("ru"),
    chantler!("rh"),
    chantler!("pd"),
    chantler!("ag"),
    chantler!("cd"),
    chantler!("in"),
    chantler!("sn"),
    chantler!("sb"),
    chantler!("te"),
    chantler!("i"),
    chantler!("xe"),
    chantler!("cs"),
    chantler!("ba"),
    chantler!("la"),
    chantler!("ce"),
    chantler!("pr"),
    chantler!("nd"),
    chantler!("pm"),
    chantler!("sm"),
    chantler!("eu"),
    chantler!("gd"),
    chantler!("tb"),
    chantler!("dy"),
    chantler!("ho"),
    chantler!("er"),
    chantler!("tm"),
    chantler!("yb"),
    chantler!("lu"),
    chantler!("hf"),
    chantler!("ta"),
    chantler!("w"),
    chantler!("re"),
    chantler!("os"),
    chantler!("ir"),
    chantler!("pt"),
    chantler!("au"),
    chantler!("hg"),
    chantler!("tl"),
    chantler!("pb"),
    chantler!("bi"),
    chantler!("po"),
    chantler!("at"),
    chantler!("rn"),
    chantler!("fr"),
    chantler!("ra"),
    chantler!("ac"),
    chantler!("th"),
    chantler!("pa"),
    chantler!("u"),
];

const ELEMENTS_CSV: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/data/elements.csv"));

/// One element: atomic number, symbol, molar mass (g/mol).
#[derive(Clone, Debug)]
pub struct Element {
    pub z: u32,
    pub symbol: String,
    pub mass: f64,
}

/// Which table of scattering factors a material's optical constants come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OpticalConstants {
    /// Henke, Gullikson & Davis (1993) as maintained by CXRO (data/henke/).
    #[default]
    Henke,
    /// Chantler (1995, 2000), NIST FFAST, with its relativistic and
    /// nuclear-Thomson corrections added to f1 (data/chantler/).
    Chantler,
}

impl OpticalConstants {
    /// The name scene files and options use.
    pub fn name(self) -> &'static str {
        match self {
            OpticalConstants::Henke => "henke",
            OpticalConstants::Chantler => "chantler",
        }
    }

    /// The table named `name`, or an error listing the names.
    pub fn parse(name: &str) -> Result<OpticalConstants, String> {
        match name {
            "henke" => Ok(OpticalConstants::Henke),
            "chantler" => Ok(OpticalConstants::Chantler),
            _ => Err(format!(
                "unknown table of optical constants `{name}` (known: henke, chantler)"
            )),
        }
    }
}

/// f1 and f2 of one element on its table's energy grid (keV, ascending),
/// restricted to where f1 is defined.
#[derive(Clone, Debug)]
pub struct ScatteringTable {
    pub energy_kev: Vec<f64>,
    pub f1: Vec<f64>,
    pub f2: Vec<f64>,
    /// ln f2 at each node (0 where f2 ≤ 0, never used there), and ln of each
    /// interval's energy ratio: the logarithms [`ScatteringTable::at`] would
    /// otherwise take on every call (the same numbers).
    ln_f2: Vec<f64>,
    ln_step: Vec<f64>,
}

impl ScatteringTable {
    fn parse(folder: &str, symbol: &str, text: &str) -> ScatteringTable {
        let mut t = ScatteringTable {
            energy_kev: Vec::new(),
            f1: Vec::new(),
            f2: Vec::new(),
            ln_f2: Vec::new(),
            ln_step: Vec::new(),
        };
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let cols: Vec<f64> = line
                .split_whitespace()
                .filter_map(|c| c.parse().ok())
                .collect();
            if cols.len() != 3 || cols[1] <= -9000.0 {
                continue; // header, comment, or f1 undefined (below ~29 eV)
            }
            let e = cols[0] * 1e-3;
            if t.energy_kev.last().is_some_and(|&last| e <= last) {
                continue; // keep the grid strictly ascending
            }
            t.energy_kev.push(e);
            t.f1.push(cols[1]);
            t.f2.push(cols[2]);
        }
        assert!(
            t.energy_kev.len() > 100,
            "data/{folder}/{}.nff: too few rows",
            symbol.to_lowercase()
        );
        t.ln_f2 =
            t.f2.iter()
                .map(|&f| if f > 0.0 { f.ln() } else { 0.0 })
                .collect();
        t.ln_step = t
            .energy_kev
            .windows(2)
            .map(|w| (w[1] / w[0]).ln())
            .collect();
        t
    }

    /// f1 and f2 at `e_kev`: f1 linearly in energy, f2 linearly in log f2 versus
    /// log E (between absorption edges f2 falls as a power of E), the
    /// interpolation periodictable uses. The caller checks the range.
    pub fn at(&self, e_kev: f64) -> (f64, f64) {
        let e = &self.energy_kev;
        let i = e.partition_point(|&x| x <= e_kev).clamp(1, e.len() - 1);
        let w = (e_kev - e[i - 1]) / (e[i] - e[i - 1]);
        let f1 = self.f1[i - 1] + w * (self.f1[i] - self.f1[i - 1]);
        let (a, b) = (self.f2[i - 1], self.f2[i]);
        let f2 = if a > 0.0 && b > 0.0 {
            let wl = (e_kev / e[i - 1]).ln() / self.ln_step[i - 1];
            let (ln_a, ln_b) = (self.ln_f2[i - 1], self.ln_f2[i]);
            (ln_a + wl * (ln_b - ln_a)).exp()
        } else {
            a + w * (b - a)
        };
        (f1, f2)
    }
}

fn elements() -> &'static [Element] {
    static ELEMENTS: OnceLock<Vec<Element>> = OnceLock::new();
    ELEMENTS.get_or_init(|| {
        ELEMENTS_CSV
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                Element {
                    z: c[0].parse().expect("data/elements.csv: Z"),
                    symbol: c[1].to_string(),
                    mass: c[2].parse().expect("data/elements.csv: mass"),
                }
            })
            .collect()
    })
}

/// The element with this symbol (case-sensitive, e.g. "Pt").
pub fn element(symbol: &str) -> Option<&'static Element> {
    elements().iter().find(|e| e.symbol == symbol)
}

/// The text of every table file (for the reflectivity cache's key: a table
/// regenerated with other numbers must not find tables built from the old).
pub fn table_files() -> impl Iterator<Item = &'static str> {
    HENKE_FILES.iter().chain(CHANTLER_FILES.iter()).copied()
}

/// Element `z`'s scattering-factor table from `constants` (parsed on first
/// use).
pub fn scattering_table(constants: OpticalConstants, z: u32) -> &'static ScatteringTable {
    type Tables = OnceLock<Vec<OnceLock<ScatteringTable>>>;
    static HENKE: Tables = OnceLock::new();
    static CHANTLER: Tables = OnceLock::new();
    let (tables, files, folder) = match constants {
        OpticalConstants::Henke => (&HENKE, &HENKE_FILES, "henke"),
        OpticalConstants::Chantler => (&CHANTLER, &CHANTLER_FILES, "chantler"),
    };
    let tables = tables.get_or_init(|| (0..92).map(|_| OnceLock::new()).collect());
    let i = (z as usize)
        .checked_sub(1)
        .filter(|&i| i < 92)
        .expect("Z in 1..=92");
    tables[i].get_or_init(|| ScatteringTable::parse(folder, &elements()[i].symbol, files[i]))
}
