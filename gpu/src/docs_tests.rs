//! The documents that describe this crate name only files that exist.

use std::path::Path;

/// Every `gpu/...` path quoted in `text` (`{a,b}` alternatives expanded).
fn quoted_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for quoted in text.split('`').skip(1).step_by(2) {
        if !quoted.starts_with("gpu/") || quoted.contains(' ') {
            continue;
        }
        match (quoted.find('{'), quoted.find('}')) {
            (Some(a), Some(b)) if a < b => {
                for alternative in quoted[a + 1..b].split(',') {
                    out.push(format!("{}{alternative}{}", &quoted[..a], &quoted[b + 1..]));
                }
            }
            _ => out.push(quoted.to_string()),
        }
    }
    out
}

#[test]
fn the_gpu_documents_name_only_files_that_exist() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut named = 0;
    for doc in ["docs/gpu.md", "docs/shadow-maps.md"] {
        let text = std::fs::read_to_string(root.join(doc)).unwrap();
        for path in quoted_paths(&text) {
            assert!(
                root.join(&path).exists(),
                "{doc} names {path}, which does not exist"
            );
            named += 1;
        }
    }
    assert!(named > 20, "only {named} paths named");
}
