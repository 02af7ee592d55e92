//! Build script of `hyst`: a release build embeds the FMU binary (crates/hyst-fmu, a cdylib) in
//! the executable, so that an installed `hyst` (`cargo install --path crates/hyst-cli`) makes
//! FMUs with nothing beside it. Cargo cannot depend on another package's cdylib, so this script
//! builds it with a nested `cargo build` into its own target directory (under OUT_DIR: the
//! outer build holds the lock of the usual one).
//!
//! `HYST_EMBED_FMU=0` builds without it (then `hyst fmu` takes `libhyst_fmu.so` beside the
//! executable or from `HYST_FMU_LIBRARY`), `=1` embeds in any profile; by default only release
//! builds embed it (debug builds and tests find the library beside the executable).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The file the embedded binary is read from (empty when nothing is embedded).
const EMBEDDED: &str = "embedded-fmu.so";

fn main() {
    println!("cargo:rerun-if-env-changed=HYST_EMBED_FMU");
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    let embedded = out_dir.join(EMBEDDED);
    let embed = match std::env::var("HYST_EMBED_FMU").as_deref() {
        Ok("0") => false,
        Ok("1") => true,
        _ => std::env::var("PROFILE").as_deref() == Ok("release"),
    };
    let bytes = if embed {
        build_fmu(&out_dir)
    } else {
        Vec::new()
    };
    if let Err(e) = std::fs::write(&embedded, bytes) {
        fail(&format!("cannot write {}: {e}", embedded.display()));
    }
}

/// Builds the FMU binary in release and returns its bytes.
fn build_fmu(out_dir: &Path) -> Vec<u8> {
    let manifest_dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let root = manifest_dir.join("../..");
    // The sources the FMU binary is built from: any change rebuilds it.
    for path in [
        "crates/hyst-fmu",
        "crates/hyst-model",
        "crates/hyst-core",
        "Cargo.toml",
        "Cargo.lock",
    ] {
        println!("cargo:rerun-if-changed={}", root.join(path).display());
    }
    let target_dir = out_dir.join("fmu-target");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut command = Command::new(cargo);
    command
        .current_dir(&root)
        .args(["build", "--release", "--locked", "-p", "hyst-fmu", "--lib"])
        .arg("--target-dir")
        .arg(&target_dir);
    // What the outer build set for itself, not for this one.
    for (key, _) in std::env::vars_os() {
        let key = key.to_string_lossy().into_owned();
        let outer = key.starts_with("CARGO_")
            && !matches!(
                key.as_str(),
                "CARGO_HOME"
                    | "CARGO_MAKEFLAGS"
                    | "CARGO_NET_OFFLINE"
                    | "CARGO_REGISTRIES_CRATES_IO_PROTOCOL"
            );
        if outer || key == "RUSTC_WORKSPACE_WRAPPER" {
            command.env_remove(&key);
        }
    }
    match command.status() {
        Ok(status) if status.success() => {}
        Ok(status) => fail(&format!(
            "building the FMU binary (cargo build --release -p hyst-fmu) failed: {status}; \
             HYST_EMBED_FMU=0 builds hyst without it"
        )),
        Err(e) => fail(&format!("cannot run cargo to build the FMU binary: {e}")),
    }
    let library = target_dir.join("release").join(library_file());
    match std::fs::read(&library) {
        Ok(bytes) => bytes,
        Err(e) => fail(&format!("cannot read {}: {e}", library.display())),
    }
}

/// The file name of the FMU binary on this platform.
fn library_file() -> &'static str {
    if cfg!(target_os = "macos") {
        "libhyst_fmu.dylib"
    } else if cfg!(windows) {
        "hyst_fmu.dll"
    } else {
        "libhyst_fmu.so"
    }
}

/// Stops the build with `message`.
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1)
}
