//! The map kept true: every source file is named in docs/solver.md's "Layout", so a file
//! added without its line there fails here.

use std::path::{Path, PathBuf};

/// The Layout's code block: the text between the fences after "## Layout".
fn layout() -> String {
    let doc = std::fs::read_to_string("docs/solver.md").expect("docs/solver.md");
    let after = doc
        .split("## Layout")
        .nth(1)
        .expect("a \"## Layout\" section");
    let block = after
        .split("```")
        .nth(1)
        .expect("a code block in the Layout");
    block.to_string()
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("src/ is readable") {
        let p = e.expect("a directory entry").path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Whether `text` names `file` (e.g. `run.rs`) as a word of its own, not inside another
/// name (`cycle_run.rs`).
fn names(text: &str, file: &str) -> bool {
    text.match_indices(file).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
    })
}

#[test]
fn every_source_file_is_in_the_layout() {
    let block = layout();
    let mut files = Vec::new();
    sources(Path::new("src"), &mut files);
    assert!(files.len() > 50, "src/ has {} files", files.len());
    let skipped = |name: &str| {
        matches!(name, "mod.rs" | "lib.rs" | "main.rs" | "tests.rs") || name.ends_with("_tests.rs")
    };
    let missing: Vec<String> = files
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_str()?;
            (!skipped(name) && !names(&block, name)).then(|| p.display().to_string())
        })
        .collect();
    assert!(
        missing.is_empty(),
        "docs/solver.md's Layout does not name: {}",
        missing.join(", ")
    );
}

#[test]
fn a_name_inside_another_is_not_named() {
    assert!(names("  run.rs  the loop", "run.rs"));
    assert!(!names("  cycle_run.rs  the loop", "run.rs"));
    assert!(names("drive.rs (the crank), run.rs (a step)", "run.rs"));
}
