//! The documentation stays true: every TOML example in README.md and docs/ is
//! read by the scene parser, and the command synopsis in docs/scene-format.md is
//! what the binary's argument definitions say.

use crate::common::{device, repo, run_ok, traxer};
use traxer::scene::desc::SceneDesc;
use traxer::scene::Scene;

/// The ```toml blocks of a Markdown file, with the line each starts on.
fn toml_blocks(text: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        match (&mut current, line.trim_start()) {
            (None, "```toml") => current = Some((i + 2, String::new())),
            (Some(_), "```") => blocks.push(current.take().unwrap()),
            (Some((_, b)), _) => {
                b.push_str(line);
                b.push('\n');
            }
            _ => {}
        }
    }
    blocks
}

/// A block split into sections (the lines before the first table header, then
/// each table), with the elisions the docs use ("...", "[table]  ...") removed.
fn sections(block: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    for line in block.lines() {
        let code = line.split('#').next().unwrap_or("").trim();
        if code == "..." {
            continue;
        }
        // A sub-table (`[magnet.campaign]`) stays with its table: alone it
        // would lack the table's required keys.
        let sub_table = code.starts_with('[') && !code.starts_with("[[") && code.contains('.');
        if code.starts_with('[') && !sub_table {
            out.push(String::new());
        }
        let line = line.split_once("  ...").map_or(line, |(head, _)| head);
        out.last_mut().unwrap().push_str(line);
        out.last_mut().unwrap().push('\n');
    }
    out.retain(|s| !s.trim().is_empty());
    out
}

/// Whether a serde error of a fragment is only what a fragment lacks: a
/// required key left out, or a `"$variable"` where a number belongs.
fn only_incomplete(message: &str) -> bool {
    message.contains("missing field") || message.contains("string \"$")
}

#[test]
fn every_toml_example_in_the_docs_reads_as_a_scene() {
    let mut files = vec![repo().join("README.md")];
    for e in std::fs::read_dir(repo().join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(p);
        }
    }
    let mut checked = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (line, block) in toml_blocks(&text) {
            let at = format!("{}:{line}", file.display());
            // A telescope prescription (data/telescopes/*.toml's form): it must
            // read and pass the prescription's checks.
            if toml::from_str::<toml::Table>(&block).is_ok_and(|t| t.contains_key("profile")) {
                let t = traxer::scene::telescope::Telescope::from_toml(&block)
                    .unwrap_or_else(|e| panic!("{at}: {e}"));
                t.validate().unwrap_or_else(|e| panic!("{at}: {e}"));
                checked += 1;
                continue;
            }
            // A whole scene has sources and objects and no elisions.
            let complete = block.contains("[[sources]]")
                && block.contains("[[objects]]")
                && toml::from_str::<toml::Table>(&block).is_ok();
            if complete {
                // A whole scene: it must build (files relative to scenes/).
                let dir = tempfile::tempdir().unwrap();
                std::os::unix::fs::symlink(repo().join("meshes"), dir.path().join("meshes"))
                    .unwrap();
                std::fs::create_dir(dir.path().join("scenes")).unwrap();
                let path = dir.path().join("scenes/example.toml");
                std::fs::write(&path, &block).unwrap();
                Scene::load(&device(), &path, &[]).unwrap_or_else(|e| panic!("{at}: {e}"));
            } else {
                // A fragment: each table must use only keys and values the
                // format has (what it leaves out is not checked).
                for section in sections(&block) {
                    toml::from_str::<toml::Table>(&section)
                        .unwrap_or_else(|e| panic!("{at}: not TOML: {e}\n{section}"));
                    if let Err(e) = toml::from_str::<SceneDesc>(&section) {
                        assert!(
                            only_incomplete(e.message()),
                            "{at}: {}\n{section}",
                            e.message()
                        );
                    }
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 10, "only {checked} TOML blocks found");
}

#[test]
fn a_wrong_key_in_a_fragment_is_caught() {
    // The check above can fail: an unknown key or a wrong type is not mistaken
    // for an incomplete fragment.
    for bad in [
        "[materials.m]\ntype = \"mirror\"\nsides = \"front\"\n",
        "[[objects]]\nname = \"x\"\nmaterial = 3\n",
        "[cameras.c]\nlook_from = [0, 0, 1]\nlook_at = [0, 0, 0]\nfov = 30.0\n",
    ] {
        let e = toml::from_str::<SceneDesc>(bad).unwrap_err();
        assert!(!only_incomplete(e.message()), "{bad}: {}", e.message());
    }
}

#[test]
fn the_command_synopsis_in_the_docs_is_the_binarys() {
    let out = run_ok(traxer().arg("synopsis"));
    let synopsis = String::from_utf8(out.stdout).unwrap();
    for file in ["README.md", "docs/scene-format.md"] {
        let doc = std::fs::read_to_string(repo().join(file)).unwrap();
        let marker = "<!-- generated by `traxer synopsis`";
        let start = doc.find(marker).expect("the synopsis marker");
        let body = &doc[start..];
        let body = &body[body.find("```\n").unwrap() + 4..];
        let body = &body[..body.find("```").unwrap()];
        assert_eq!(
            body.trim_end(),
            synopsis.trim_end(),
            "{file}'s command line differs from `traxer synopsis`: paste its output"
        );
    }
    // Every visible subcommand is in it.
    let help = String::from_utf8(run_ok(traxer().arg("--help")).stdout).unwrap();
    let commands = help
        .split("Commands:")
        .nth(1)
        .unwrap()
        .split("Options:")
        .next()
        .unwrap();
    for line in commands.lines() {
        let Some(cmd) = line.split_whitespace().next() else {
            continue;
        };
        if cmd != "help" {
            assert!(
                synopsis.contains(&format!("traxer {cmd} "))
                    || synopsis.contains(&format!("traxer {cmd}\n")),
                "{cmd} missing from the synopsis"
            );
        }
    }
}

/// Every script answers `--help` with what it does, and does nothing else (a
/// script regenerating docs or meshes must not start on `--help`).
#[test]
fn every_script_answers_help() {
    let dir = crate::common::repo().join("scripts");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let runner = match path.extension().and_then(|e| e.to_str()) {
            Some("sh") => "bash",
            Some("py") => "python3",
            _ => continue,
        };
        let out = std::process::Command::new(runner)
            .arg(&path)
            .arg("--help")
            .env("PATH", std::env::var_os("PATH").unwrap_or_default())
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}: --help failed: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            text.trim().len() > 40,
            "{}: --help says {text:?}",
            path.display()
        );
        checked += 1;
    }
    assert!(checked >= 15);
}
