//! docs/scene-format.md, the scene language's reference, against the parser: every block
//! the parser accepts has a section, every attribute a row in its block's table, and the
//! page names no block or attribute the parser does not take; its example is a valid scene.

use microray::error::Entity;
use microray::parse::{attributes_of, no_textures, parse_scene};

const PAGE: &str = include_str!("../docs/scene-format.md");

/// Each `### `keyword`` section: its keyword and its text.
fn sections() -> Vec<(&'static str, &'static str)> {
    let mut found = Vec::new();
    for part in PAGE.split("\n### ").skip(1) {
        let (heading, body) = part.split_once('\n').unwrap();
        let keyword = heading.trim().trim_matches('`');
        let body = body.split("\n## ").next().unwrap();
        found.push((keyword, body));
    }
    found
}

/// The attributes named in the first column of a section's table.
fn table_attributes(body: &str) -> Vec<&str> {
    body.lines()
        .filter(|l| l.starts_with("| `"))
        .flat_map(|l| l.split('|').nth(1).unwrap().split(','))
        .map(|a| a.trim().trim_matches('`'))
        .collect()
}

#[test]
fn every_block_and_attribute_is_documented() {
    let sections = sections();
    for entity in Entity::ALL {
        let keyword = entity.keyword();
        let (_, body) = sections
            .iter()
            .find(|(k, _)| *k == keyword)
            .unwrap_or_else(|| panic!("no section for `{keyword}`"));
        let documented = table_attributes(body);
        for attr in attributes_of(entity) {
            assert!(
                documented.contains(&attr.keyword()),
                "`{keyword}`'s table has no row for `{}`",
                attr.keyword()
            );
        }
        for name in documented {
            assert!(
                attributes_of(entity).iter().any(|a| a.keyword() == name),
                "`{keyword}`'s table names `{name}`, which the parser does not take there"
            );
        }
    }
    for (keyword, _) in sections {
        assert!(
            Entity::ALL.iter().any(|e| e.keyword() == keyword),
            "a section for `{keyword}`, which is not a block"
        );
    }
}

#[test]
fn the_example_is_a_scene() {
    let example = PAGE
        .split("```text\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .unwrap();
    let scene: microray::Scene<'_, f64> = parse_scene(example.as_bytes(), no_textures).unwrap();
    assert_eq!((scene.objects().len(), scene.materials().len()), (2, 2));
}
