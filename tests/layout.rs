//! The map of where things live (`docs/layout.md`) names files that exist.

use std::path::Path;

/// The quoted paths of a Markdown text: the `code` spans that hold a `/`.
fn quoted_paths(text: &str) -> Vec<&str> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|span| span.contains('/') && !span.contains(' '))
        .collect()
}

#[test]
fn every_file_the_layout_map_names_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let map = std::fs::read_to_string(root.join("docs/layout.md")).unwrap();
    let paths = quoted_paths(&map);
    assert!(paths.len() > 20, "{paths:?}");
    let missing: Vec<&&str> = paths.iter().filter(|p| !root.join(p).exists()).collect();
    assert!(
        missing.is_empty(),
        "docs/layout.md names missing files: {missing:?}"
    );
    // The README points at the map.
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    assert!(readme.contains("docs/layout.md"));
}
