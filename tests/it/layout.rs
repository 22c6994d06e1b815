//! The shape of the code (ARCHITECTURE.md): the library's top-level modules
//! import each other without cycles, no source file grows past 600 lines, and
//! `unsafe` appears only in `embree/`.

use crate::common::repo;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The code of a file without its comments (line comments only: the crate
/// writes no block comments).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) if !l[..i].contains('"') => &l[..i],
            _ => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Top-level library module → the top-level modules it names as `crate::X`
/// (single paths and `crate::{a, b::c}` groups).
fn module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = repo().join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let top = |p: &Path| -> Option<String> {
        let rel = p.strip_prefix(&src).unwrap();
        let first = rel.components().next()?.as_os_str().to_string_lossy();
        let name = first.trim_end_matches(".rs").to_string();
        (!matches!(name.as_str(), "lib" | "main" | "cli")).then_some(name)
    };
    let modules: BTreeSet<String> = files.iter().filter_map(|p| top(p)).collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = modules
        .iter()
        .map(|m| (m.clone(), BTreeSet::new()))
        .collect();
    for f in &files {
        let Some(from) = top(f) else { continue };
        let text = code(&std::fs::read_to_string(f).unwrap());
        for n in names_after(&text, "crate::") {
            if modules.contains(&n) && n != from {
                graph.get_mut(&from).unwrap().insert(n);
            }
        }
    }
    graph
}

/// The first path segments named after each `prefix` in `text` (`prefix` then
/// `a::…`, or a group `{a, b::c, d::{e, f}}`: a, b, d).
fn names_after(text: &str, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices(prefix) {
        let rest = &text[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut items = vec![String::new()];
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => items.push(String::new()),
                    _ => items.last_mut().unwrap().push(c),
                }
            }
            out.extend(
                items
                    .iter()
                    .map(|s| s.trim().split("::").next().unwrap_or("").to_string()),
            );
        } else {
            out.push(
                rest.chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect(),
            );
        }
    }
    out
}

/// A cycle of the graph, if it has one (depth-first search).
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        path.push(n.to_string());
        for m in &graph[n] {
            match state.get(m.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = path.iter().position(|p| p == m).unwrap();
                    let mut cycle = path[start..].to_vec();
                    cycle.push(m.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(m, graph, state, path) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in graph.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, graph, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn library_modules_import_each_other_without_cycles() {
    let graph = module_graph();
    // The graph is read correctly: known edges are there.
    assert!(graph["trace"].contains("raycast"), "{graph:?}");
    assert!(graph["scene"].contains("geometry"), "{graph:?}");
    if let Some(cycle) = find_cycle(&graph) {
        panic!("module cycle: {}", cycle.join(" → "));
    }
    // The lower layers know nothing of the upper ones.
    for (low, forbidden) in [
        ("geometry", ["embree", "render", "output", "scene", "trace"]),
        ("xray", ["embree", "render", "output", "scene", "trace"]),
        ("source", ["embree", "render", "output", "scene", "trace"]),
        ("files", ["embree", "render", "output", "scene", "trace"]),
    ] {
        for f in forbidden {
            assert!(!graph[low].contains(f), "{low} imports {f}");
        }
    }
    // Leaves: the physical constants and the colour map import nothing, so that
    // `render` and `output` share the colour map without one importing the other.
    for leaf in ["constants", "colormap", "files", "text"] {
        assert!(graph[leaf].is_empty(), "{leaf} imports {:?}", graph[leaf]);
    }
    assert!(!graph["render"].contains("output"), "render imports output");
}

/// The files of one folder (a module's children) that import each other in a
/// circle: the folders whose sibling files (and subfolders) name each other
/// through `super::` or their full `crate::` path in a cycle, with the cycle.
fn file_circles() -> BTreeMap<String, Vec<String>> {
    let src = repo().join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut folders: BTreeMap<PathBuf, Vec<PathBuf>> = BTreeMap::new();
    for f in files {
        folders
            .entry(f.parent().unwrap().to_path_buf())
            .or_default()
            .push(f);
    }
    let mut circles = BTreeMap::new();
    for (dir, files) in folders {
        if dir == src {
            continue;
        }
        let stem = |p: &Path| p.file_stem().unwrap().to_string_lossy().into_owned();
        let mut siblings: BTreeSet<String> = files.iter().map(|f| stem(f)).collect();
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                siblings.insert(stem(&p));
            }
        }
        siblings.remove("mod");
        let rel = dir
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('/', "::");
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for f in files.iter().filter(|f| stem(f) != "mod") {
            let text = code(&std::fs::read_to_string(f).unwrap());
            let text = text.split("#[cfg(test)]").next().unwrap();
            let named = names_after(text, "super::")
                .into_iter()
                .chain(names_after(text, &format!("crate::{rel}::")));
            let edges = graph.entry(stem(f)).or_default();
            edges.extend(named.filter(|n| siblings.contains(n) && *n != stem(f)));
        }
        if let Some(cycle) = find_cycle(&graph) {
            circles.insert(format!("src/{}", rel.replace("::", "/")), cycle);
        }
    }
    circles
}

#[test]
fn files_in_a_folder_import_each_other_without_circles() {
    // A circle between sibling files is cut by moving one type (or one
    // function, or merging two files): none is left.
    let circles: Vec<String> = file_circles()
        .into_iter()
        .map(|(folder, cycle)| format!("{folder}: {}", cycle.join(" → ")))
        .collect();
    assert!(
        circles.is_empty(),
        "files that import each other in a circle: {circles:?}"
    );
}

#[test]
fn the_cycle_finder_finds_cycles() {
    let g: BTreeMap<String, BTreeSet<String>> = [("a", "b"), ("b", "c"), ("c", "a")]
        .iter()
        .map(|(x, y)| (x.to_string(), BTreeSet::from([y.to_string()])))
        .collect();
    assert_eq!(find_cycle(&g).unwrap().len(), 4);
}

#[test]
fn no_source_file_is_over_600_lines_and_unsafe_stays_in_embree() {
    let mut files = Vec::new();
    rust_files(&repo().join("src"), &mut files);
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let n = text.lines().count();
        assert!(n <= 600, "{}: {n} lines", f.display());
        let in_embree = f.components().any(|c| c.as_os_str() == "embree");
        if !in_embree {
            assert!(
                !code(&text).contains("unsafe "),
                "{}: unsafe outside embree/",
                f.display()
            );
        }
    }
}

/// (lines, file, name) of every function with a body in `text`: from its `fn`
/// line to the line that closes its body (braces counted; the crate writes no
/// braces in character literals that would fool this).
fn function_lengths(text: &str) -> Vec<(usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim_start();
        let l = l
            .strip_prefix("pub(crate) ")
            .or_else(|| l.strip_prefix("pub(super) "))
            .or_else(|| l.strip_prefix("pub "))
            .unwrap_or(l);
        let Some(rest) = l.strip_prefix("fn ") else {
            i += 1;
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let (mut depth, mut opened, mut j) = (0i64, false, i);
        while j < lines.len() {
            let code = code(lines[j]);
            if !opened && code.trim_end().ends_with(';') {
                break; // a declaration without a body
            }
            for c in code.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if opened && depth == 0 {
                out.push((j - i + 1, name.clone()));
                break;
            }
            j += 1;
        }
        i = j.max(i) + 1;
    }
    out
}

#[test]
fn no_function_is_over_100_lines_and_commands_only_build_run_and_print() {
    let src = repo().join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut long = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let command = f.parent() == Some(&src.join("cli"));
        for (n, name) in function_lengths(&text) {
            let limit = if command && name == "run" { 70 } else { 100 };
            if n > limit {
                long.push(format!(
                    "{}: {name} has {n} lines (at most {limit})",
                    f.display()
                ));
            }
        }
    }
    assert!(long.is_empty(), "{long:#?}");
    // The counter counts.
    let sample = "fn a() {\n    if x {\n        y();\n    }\n}\nfn b();\npub fn c() { }\n";
    assert_eq!(
        function_lengths(sample),
        vec![(5, "a".to_string()), (1, "c".to_string())]
    );
}

#[test]
fn provenance_is_built_only_in_run() {
    // One record per kind of result (run, study, picture, table), made in
    // src/run/provenance.rs: no front end assembles its own.
    let mut files = Vec::new();
    rust_files(&repo().join("src"), &mut files);
    rust_files(&repo().join("python/src"), &mut files);
    rust_files(&repo().join("examples"), &mut files);
    let home = repo().join("src/run/provenance.rs");
    let mut found = Vec::new();
    for f in files.iter().filter(|f| **f != home) {
        let text = std::fs::read_to_string(f).unwrap();
        let code = code(&text);
        let built = code.matches("Provenance {").count()
            - code.matches("struct Provenance {").count()
            - code.matches("impl Provenance {").count()
            - code.matches("-> Provenance {").count();
        if code.contains("Provenance::new(") || built > 0 {
            found.push(f.display().to_string());
        }
    }
    assert!(
        found.is_empty(),
        "provenance assembled outside run/provenance.rs: {found:?}"
    );
    // The check sees a construction where there is one.
    let text = std::fs::read_to_string(&home).unwrap();
    assert!(code(&text).contains("Provenance {"));
}

#[test]
fn studies_are_opened_and_recorded_only_by_the_study_job() {
    // A study's life (its folder and record opened, its provenance) belongs to
    // run/ (`run::run_study`): front ends parse arguments into a study's
    // settings and show its output. A results folder is put in place only
    // there too (`run::write_results_folder`): no front end stages, writes
    // and commits by hand.
    let found = files_containing(
        &["src", "python/src"],
        |rel| rel.starts_with("src/run/") || rel.starts_with("src/files/"),
        &[
            "Study::open(",
            "Provenance::of_study(",
            "OutputFolder::prepare(",
            "folder.commit()",
            "out.commit()",
        ],
    );
    assert!(
        found.is_empty(),
        "studies opened, given provenance or results put in place outside run/: {found:?}"
    );
    // The check sees them where they are.
    for (f, what) in [
        ("src/run/study_job.rs", "Study::<"),
        ("src/run/finished.rs", "folder.commit()"),
        ("src/run/finished.rs", "Provenance::of_study("),
    ] {
        let code = code(&std::fs::read_to_string(repo().join(f)).unwrap());
        assert!(code.contains(what), "{f} no longer has {what}");
    }
}

#[test]
fn the_library_reads_the_environment_only_in_environment_rs() {
    // The physics reads its settings from its arguments; the few environment
    // variables the library honours (the reflectivity cache's folder and
    // bound) are read in src/environment.rs. The front ends (src/cli/,
    // main.rs) read what they like.
    let found = files_containing(
        &["src"],
        |rel| rel.starts_with("src/cli/") || rel == "src/main.rs" || rel == "src/environment.rs",
        &["env::var"],
    );
    assert!(
        found.is_empty(),
        "environment read outside src/environment.rs: {found:?}"
    );
    let home = std::fs::read_to_string(repo().join("src/environment.rs")).unwrap();
    assert!(
        code(&home).contains("env::var"),
        "the check sees a read where there is one"
    );
}

#[test]
fn photon_chunks_are_looped_over_only_in_trace() {
    // One photon driver: runs, systematics variations and PSF points hand
    // `trace::run_part_with` how to trace a chunk; the effective area and the
    // sky calibration, which keep per photon what a tally does not, hand
    // `trace::map_chunks` what to keep of one.
    let found = files_containing(
        &["src", "python/src"],
        |rel| rel.starts_with("src/trace/"),
        &["chunk_range(", "div_ceil(CHUNK)"],
    );
    assert!(
        found.is_empty(),
        "photon chunks looped over outside trace/: {found:?}"
    );
}

/// The source files under `dirs` (repository-relative), apart from those
/// `skip` names, whose code (comments left out) contains any of `needles`.
fn files_containing(dirs: &[&str], skip: impl Fn(&str) -> bool, needles: &[&str]) -> Vec<String> {
    let mut files = Vec::new();
    for d in dirs {
        rust_files(&repo().join(d), &mut files);
    }
    files
        .iter()
        .filter_map(|f| {
            let rel = f
                .strip_prefix(repo())
                .unwrap()
                .to_string_lossy()
                .to_string();
            let code = code(&std::fs::read_to_string(f).unwrap());
            (!skip(&rel) && needles.iter().any(|n| code.contains(n))).then_some(rel)
        })
        .collect()
}
