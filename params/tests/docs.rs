//! The reference of the shadow-map tables in `docs/scene-format.md` is [`toml_reference`]'s
//! output, so the docs cannot drift from `PARAMS`. On a mismatch the test prints the block to
//! paste.

use penumbra_params::toml_reference;

#[test]
fn scene_format_docs_hold_the_generated_reference() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/scene-format.md");
    let docs = std::fs::read_to_string(path).unwrap();
    let block = format!("```toml\n{}```\n", toml_reference());
    assert!(
        docs.contains(&block),
        "docs/scene-format.md lacks the generated reference of the shadow-map tables; it is:\n{block}"
    );
}
