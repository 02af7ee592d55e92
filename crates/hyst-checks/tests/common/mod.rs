//! Replays a directory of fuzz inputs (`fuzz/<kind>/<target>/`) through one of the checks the fuzz
//! targets call: shared by the corpus and the regression tests.

use std::path::PathBuf;

/// Runs `check` on every file of `fuzz/<kind>/<target>/` (at least `at_least` of them) and fails
/// listing every file whose check failed.
pub fn replay(kind: &str, target: &str, check: fn(&[u8]) -> Result<(), String>, at_least: usize) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz")
        .join(kind)
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(
        files.len() >= at_least,
        "{}: only {} files, expected at least {at_least}",
        dir.display(),
        files.len()
    );
    let mut broken = Vec::new();
    for file in &files {
        let data = std::fs::read(file).unwrap();
        if let Err(e) = check(&data) {
            broken.push(format!("{}: {e}", file.display()));
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}
