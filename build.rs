//! Build script: finds the system's Intel Embree (3 or 4), runs bindgen against the
//! headers of exactly the library that is linked, and tells the crate which major
//! version it got (`cfg(embree4)` or `cfg(embree3)`).
//!
//! Search order (the convention of the Rust Embree crates):
//! 1. `EMBREE_INCLUDE_DIR` and `EMBREE_LIB_DIR` (finer overrides),
//! 2. `EMBREE_DIR` (a folder with `include/` and `lib/`),
//! 3. the usual system prefixes.
//!
//! Embree ships no pkg-config file, so the major version is read from which header
//! exists: `embree4/rtcore.h` or `embree3/rtcore.h` (Embree 4 preferred).

use std::env;
use std::path::{Path, PathBuf};

const INSTALL_HINT: &str = "\
traxer needs Intel Embree (3.13 or 4.x) and libclang to build.
  Debian / Ubuntu:  sudo apt-get install libembree-dev libclang-dev
  (or run ./scripts/setup.sh, which does this for you)
  Embree elsewhere: set EMBREE_DIR to a folder holding include/embree4 (or include/embree3)
                    and lib/, or set EMBREE_INCLUDE_DIR and EMBREE_LIB_DIR.";

fn main() {
    for var in ["EMBREE_DIR", "EMBREE_INCLUDE_DIR", "EMBREE_LIB_DIR"] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo::rustc-check-cfg=cfg(embree3)");
    println!("cargo::rustc-check-cfg=cfg(embree4)");

    record_git_hash();
    list_shipped_telescopes();

    let (include_dir, lib_dir) = candidate_dirs();
    let Some((include_dir, major)) = include_dir
        .iter()
        .find_map(|dir| detect_major(dir).map(|m| (dir.clone(), m)))
    else {
        fail(&format!(
            "could not find embree4/rtcore.h or embree3/rtcore.h in any of: {}",
            include_dir
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    };
    let lib_name = format!("embree{major}");

    if let Some(dir) = lib_dir.iter().find(|d| has_library(d, &lib_name)) {
        println!("cargo:rustc-link-search=native={}", dir.display());
        // Non-system locations also get an rpath so that the binary runs without
        // LD_LIBRARY_PATH.
        if !dir.starts_with("/usr/lib") && !dir.starts_with("/lib") {
            println!("cargo:rustc-link-arg=-Wl,-rpath,{}", dir.display());
        }
    } else if env::var_os("EMBREE_LIB_DIR").is_some() || env::var_os("EMBREE_DIR").is_some() {
        fail(&format!(
            "found the Embree {major} headers in {} but no lib{lib_name}.so in {}",
            include_dir.display(),
            lib_dir
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    println!("cargo:rustc-link-lib=dylib={lib_name}");
    println!("cargo:rustc-cfg=embree{major}");

    let header = include_dir.join(format!("embree{major}/rtcore.h"));
    println!("cargo:rerun-if-changed={}", header.display());
    let bindings = bindgen::Builder::default()
        .header(header.to_string_lossy())
        .clang_arg(format!("-I{}", include_dir.display()))
        .allowlist_function("rtc.*")
        .allowlist_type("RTC.*")
        .allowlist_var("RTC.*")
        .default_enum_style(bindgen::EnumVariation::Consts)
        .prepend_enum_name(false)
        .layout_tests(true)
        .derive_default(true)
        .generate()
        .unwrap_or_else(|e| fail(&format!("bindgen failed on {}: {e}", header.display())));
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let text = bindings.to_string();
    // Embree 4.3+ built with instance arrays adds `instPrimID` to the query context.
    println!("cargo::rustc-check-cfg=cfg(embree_inst_prim_id)");
    if text.contains("pub instPrimID") {
        println!("cargo:rustc-cfg=embree_inst_prim_id");
    }
    std::fs::write(out.join("embree_bindings.rs"), text)
        .unwrap_or_else(|e| fail(&format!("cannot write bindings: {e}")));
}

/// Puts the git commit into `TRAXER_GIT_HASH` for provenance ("unknown" outside a
/// git checkout).
fn record_git_hash() {
    let git = |args: &[&str]| {
        // No optional locks: `git status` would otherwise refresh the index,
        // which this script watches, and every build would rebuild the crate.
        std::process::Command::new("git")
            .env("GIT_OPTIONAL_LOCKS", "0")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let mut hash = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_else(|| "unknown".into());
    if git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty()) {
        hash.push_str("-dirty");
    }
    println!("cargo:rustc-env=TRAXER_GIT_HASH={hash}");
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        println!("cargo:rerun-if-changed={dir}/HEAD");
        println!("cargo:rerun-if-changed={dir}/index");
    }
}

/// Writes `$OUT_DIR/telescopes.rs`: every data/telescopes/NAME.toml compiled in
/// under NAME, so that a new telescope takes its data file and nothing else.
fn list_shipped_telescopes() {
    let dir = Path::new(&env::var("CARGO_MANIFEST_DIR").unwrap()).join("data/telescopes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    let entries: String = files
        .iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy();
            format!(
                "    ({name:?}, include_str!({:?})),\n",
                p.display().to_string()
            )
        })
        .collect();
    let code = format!(
        "/// The telescopes of data/telescopes/, by file name (written by build.rs).\n\
         pub const SHIPPED: [(&str, &str); {}] = [\n{entries}];\n",
        files.len()
    );
    let out = Path::new(&env::var("OUT_DIR").unwrap()).join("telescopes.rs");
    std::fs::write(out, code).expect("OUT_DIR is writable");
}

/// Include and library folders to try, in order of preference.
fn candidate_dirs() -> (Vec<PathBuf>, Vec<PathBuf>) {
    let mut inc = Vec::new();
    let mut lib = Vec::new();
    if let Some(d) = env::var_os("EMBREE_INCLUDE_DIR") {
        inc.push(PathBuf::from(d));
    }
    if let Some(d) = env::var_os("EMBREE_LIB_DIR") {
        lib.push(PathBuf::from(d));
    }
    if let Some(d) = env::var_os("EMBREE_DIR") {
        let d = PathBuf::from(d);
        inc.push(d.join("include"));
        lib.push(d.join("lib"));
        lib.push(d.join("lib64"));
    }
    if inc.is_empty() {
        for p in [
            "/usr/local/include",
            "/usr/include",
            "/opt/homebrew/include",
        ] {
            inc.push(PathBuf::from(p));
        }
    }
    if lib.is_empty() {
        let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
        for p in [
            "/usr/local/lib".to_string(),
            format!("/usr/lib/{arch}-linux-gnu"),
            "/usr/lib64".to_string(),
            "/usr/lib".to_string(),
            "/opt/homebrew/lib".to_string(),
        ] {
            lib.push(PathBuf::from(p));
        }
    }
    (inc, lib)
}

fn detect_major(include_dir: &Path) -> Option<u32> {
    [4, 3]
        .into_iter()
        .find(|m| include_dir.join(format!("embree{m}/rtcore.h")).is_file())
}

fn has_library(dir: &Path, name: &str) -> bool {
    ["so", "dylib", "a"]
        .iter()
        .any(|ext| dir.join(format!("lib{name}.{ext}")).exists())
}

fn fail(msg: &str) -> ! {
    eprintln!("\nerror: {msg}\n\n{INSTALL_HINT}\n");
    std::process::exit(1);
}
