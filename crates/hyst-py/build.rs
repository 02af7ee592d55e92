//! Build script of the Python extension: compiles the MuJoCo actuator plugins
//! (crates/hyst-capi/mujoco/hyst_mujoco.c, docs/mujoco.md) into the extension, against the
//! headers of the `mujoco` package the build's Python has (the wheel's build requires it,
//! pyproject.toml), or of `HYST_MUJOCO_INCLUDE` (a directory holding `mujoco/mujoco.h`).
//! Without them it compiles hyst_mujoco_absent.c instead: the extension has no plugins, and
//! `hyst.mujoco.load()` says so; `cargo build` and `cargo clippy` of the workspace need no MuJoCo.
//!
//! The plugins call hyst's C API (hyst-capi, linked into the extension) directly and MuJoCo
//! through the functions `hyst.mujoco.load()` passes from the libmujoco the `mujoco` package
//! loaded, so the extension itself does not link libmujoco.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=HYST_MUJOCO_INCLUDE");
    println!("cargo:rerun-if-env-changed=PYO3_PYTHON");
    let root =
        PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default()).join("../..");
    let source = root.join("crates/hyst-capi/mujoco");
    println!("cargo:rerun-if-changed={}", source.display());
    let mut build = cc::Build::new();
    build
        .std("c11")
        // Optimised in every profile: the plugins run inside each mj_step, and a dev build's
        // -O0 would make their cost the build's rather than the method's.
        .opt_level(2)
        .warnings_into_errors(true);
    let Some(include) = mujoco_include() else {
        // No plugins: `hyst_mujoco_register` says why (the Rust side is the same either way,
        // so `cargo clippy` of the workspace checks all of it).
        build
            .file(source.join("hyst_mujoco_absent.c"))
            .compile("hyst_mujoco");
        return;
    };
    build
        .file(source.join("hyst_mujoco.c"))
        .include(&include)
        .include(&source)
        .include(root.join("include"))
        .compile("hyst_mujoco");
    // The version the plugins are compiled for (mujoco.h's mjVERSION_HEADER, 4000001 for
    // 4.0.1): `hyst.mujoco.load()` compares it with the loaded libmujoco's.
    let header = std::fs::read_to_string(include.join("mujoco/mujoco.h")).unwrap_or_default();
    let version = header
        .lines()
        .find_map(|l| l.trim().strip_prefix("#define mjVERSION_HEADER"))
        .map_or("0", str::trim);
    println!("cargo:rustc-env=HYST_MUJOCO_VERSION={version}");
}

/// The directory that holds `mujoco/mujoco.h`: `HYST_MUJOCO_INCLUDE`, or the `include` folder
/// of the `mujoco` package the build's Python finds (found without importing it).
fn mujoco_include() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("HYST_MUJOCO_INCLUDE") {
        return Some(PathBuf::from(dir));
    }
    let python = std::env::var_os("PYO3_PYTHON").unwrap_or_else(|| "python3".into());
    let output = Command::new(python)
        .args([
            "-c",
            "import importlib.util, os; s = importlib.util.find_spec('mujoco'); \
             print(os.path.join(os.path.dirname(s.origin), 'include') if s else '')",
        ])
        .output()
        .ok()?;
    let text = String::from_utf8(output.stdout).ok()?;
    let dir = PathBuf::from(text.trim());
    dir.join("mujoco/mujoco.h").is_file().then_some(dir)
}
