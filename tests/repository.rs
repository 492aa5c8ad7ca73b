//! The repository's documents against the code: the README stays short and its examples
//! are the code CI builds, every relative link in the README and docs/ leads somewhere, no
//! command points outside the repository, and every cargo feature is in the feature
//! tables. (Not in the packaged crate, which carries neither the firmware nor docs/.)

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The fenced code blocks of a Markdown text whose info string starts with `lang`.
fn blocks<'a>(text: &'a str, lang: &str) -> Vec<&'a str> {
    let mut found = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find("```") {
        let after = &rest[start + 3..];
        let (info, body) = after.split_once('\n').unwrap();
        let end = body.find("```").unwrap();
        if info.trim().starts_with(lang) {
            found.push(&body[..end]);
        }
        rest = &body[end + 3..];
    }
    found
}

#[test]
fn the_readme_is_short() {
    let lines = read("README.md").lines().count();
    assert!(lines <= 300, "README.md has {lines} lines");
}

#[test]
fn the_readme_firmware_example_is_the_quick_start_ci_builds() {
    let readme = read("README.md");
    let quickstart = read("firmware/quickstart/src/lib.rs");
    let rust = blocks(&readme, "rust");
    assert!(
        rust.contains(&quickstart.as_str()),
        "README.md has no rust block equal to firmware/quickstart/src/lib.rs"
    );
    // The dependency line, as the quick start's Cargo.toml has it but for the path.
    let manifest = read("firmware/quickstart/Cargo.toml");
    let line = manifest
        .lines()
        .find(|l| l.starts_with("microray = "))
        .unwrap()
        .replace(r#", path = "../..""#, "");
    let toml = blocks(&readme, "toml");
    assert!(
        toml.iter().any(|b| b.trim() == line),
        "README.md has no toml block `{line}`"
    );
    // And the crate docs give the same line.
    assert!(read("src/lib.rs").contains(&format!("//! {line}")));
}

#[test]
fn the_readme_library_example_is_the_crate_docs_tested_one() {
    let readme = read("README.md");
    let lib = read("src/lib.rs");
    // The first example of the crate docs, as rustdoc shows it (hidden `# ` lines left out).
    let docs: String = lib
        .lines()
        .filter_map(|l| l.strip_prefix("//!"))
        .map(|l| l.strip_prefix(' ').unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n");
    let example = blocks(&docs, "")[0];
    let shown: String = example
        .lines()
        .filter(|l| !l.starts_with("# "))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(
        blocks(&readme, "rust").contains(&shown.as_str()),
        "README.md's library example differs from src/lib.rs's first doc example:\n{shown}"
    );
}

/// Markdown files whose links are checked.
fn documents() -> Vec<PathBuf> {
    let mut all = vec![root().join("README.md"), root().join("CHANGELOG.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    all.extend(docs);
    all
}

/// The targets of `](...)` links and images.
fn links(text: &str) -> Vec<&str> {
    text.split("](")
        .skip(1)
        .filter_map(|rest| rest.split_once(')').map(|(target, _)| target))
        .collect()
}

#[test]
fn every_relative_link_leads_to_a_file() {
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        for target in links(&text) {
            if target.contains("://") || target.starts_with('#') {
                continue;
            }
            let file = target.split('#').next().unwrap();
            let path = doc.parent().unwrap().join(file);
            assert!(
                path.exists(),
                "{}: link to {target}: no such file",
                doc.display()
            );
        }
    }
}

#[test]
fn no_command_points_outside_the_repository() {
    for doc in [
        "README.md",
        "docs/scene-format.md",
        "docs/design.md",
        "docs/panels.md",
    ] {
        let text = read(doc);
        assert!(!text.contains("../shared"), "{doc} points at ../shared");
    }
}

#[test]
fn the_package_readme_has_only_absolute_links() {
    let text = read("docs/crates-io.md");
    for target in links(&text) {
        assert!(
            target.contains("://"),
            "docs/crates-io.md: relative link {target}"
        );
    }
    assert!(!text.contains("!["), "docs/crates-io.md shows a picture");
}

#[test]
fn every_cargo_feature_is_in_the_feature_tables() {
    let manifest = read("Cargo.toml");
    let features = manifest
        .split("[features]")
        .nth(1)
        .unwrap()
        .split("\n[")
        .next()
        .unwrap();
    let names: Vec<&str> = features
        .lines()
        .filter(|l| !l.starts_with(' ') && !l.starts_with('#') && !l.starts_with(']'))
        .filter_map(|l| l.split_once(" = ").map(|(name, _)| name.trim()))
        .filter(|name| *name != "default")
        .collect();
    assert!(names.len() >= 15, "{names:?}");
    for (doc, text) in [
        ("README.md", read("README.md")),
        ("src/lib.rs", read("src/lib.rs")),
    ] {
        let table: Vec<&str> = text
            .lines()
            .map(|l| l.trim_start_matches("//! "))
            .filter(|l| l.starts_with("| `"))
            .collect();
        for name in &names {
            assert!(
                table.iter().any(|row| {
                    let first = row.split('|').nth(1).unwrap_or("");
                    first.contains(&format!("`{name}`"))
                }),
                "{doc}'s feature table misses `{name}`"
            );
        }
    }
}
