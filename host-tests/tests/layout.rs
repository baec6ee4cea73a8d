//! The dependency rules of `host_tests` (its crate docs), checked on the source: the oracle
//! shares nothing with the core it judges, the lower layers never reach up, and commands
//! never use each other.

use std::path::{Path, PathBuf};

fn sources(dir: &str) -> Vec<(PathBuf, String)> {
    fn walk(dir: &Path, out: &mut Vec<(PathBuf, String)>) {
        for entry in std::fs::read_dir(dir).expect("source folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                // Code only: what the docs mention is not a dependency.
                let text = std::fs::read_to_string(&path)
                    .expect("source file")
                    .lines()
                    .filter(|l| !l.trim_start().starts_with("//"))
                    .collect::<Vec<_>>()
                    .join("\n");
                out.push((path, text));
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(dir);
    let mut out = vec![];
    walk(&root, &mut out);
    assert!(!out.is_empty(), "no sources in {}", root.display());
    out
}

/// Every `crate::<module>` path named in `text`.
fn crate_paths(text: &str) -> Vec<String> {
    text.match_indices("crate::")
        .filter(|(i, _)| !text[..*i].ends_with("host_"))
        .map(|(i, _)| {
            text[i + 7..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

/// `dir` names nothing of the core or the app, and of this crate only `allowed` modules.
fn only(dir: &str, allowed: &[&str]) {
    for (path, text) in sources(dir) {
        for foreign in ["imu_core", "imu_app"] {
            assert!(
                !text.contains(foreign),
                "{} uses {foreign}: the {dir} layer must not",
                path.display()
            );
        }
        for module in crate_paths(&text) {
            assert!(
                allowed.contains(&module.as_str()),
                "{} uses crate::{module}; {dir} may use only {allowed:?}",
                path.display()
            );
        }
    }
}

#[test]
fn the_oracle_shares_nothing_with_the_core() {
    only("oracle", &["oracle"]);
}

#[test]
fn statistics_and_formats_stand_alone() {
    only("stats", &["stats"]);
    only("formats", &["formats"]);
}

#[test]
fn the_world_makes_codes_and_never_runs_the_core() {
    only("world", &["world", "stats"]);
}

#[test]
fn the_device_layer_does_not_reach_up_to_commands() {
    // The formats stand alone (above), so the device may use them (a number in a message, a
    // quoted line) without a cycle.
    for (path, text) in sources("device") {
        for module in crate_paths(&text) {
            assert!(
                ["device", "world", "stats", "formats"].contains(&module.as_str()),
                "{} uses crate::{module}",
                path.display()
            );
        }
    }
}

#[test]
fn commands_never_use_each_other() {
    let commands: Vec<String> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/commands"))
            .expect("commands folder")
            .map(|e| {
                let p = e.expect("entry").path();
                p.file_stem().expect("name").to_string_lossy().into_owned()
            })
            .filter(|n| n != "mod")
            .collect();
    assert!(commands.len() >= 11, "{commands:?}");
    for (path, text) in sources("commands") {
        let own = path
            .strip_prefix(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/commands"))
            .expect("under commands")
            .components()
            .next()
            .expect("a component")
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        for other in commands.iter().filter(|c| **c != own) {
            for pattern in [format!("commands::{other}"), format!("super::{other}")] {
                assert!(
                    !text.contains(&pattern),
                    "{} uses {pattern}: commands share through the layers below",
                    path.display()
                );
            }
        }
    }
}
