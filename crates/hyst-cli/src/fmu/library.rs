//! The FMU binary that `hyst fmu` packs: found (the environment, the copy a release build
//! embeds, or the file beside `hyst`), read and checked.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// The environment variable that names the FMU binary (`libhyst_fmu.so`) to pack.
pub const LIBRARY_ENV: &str = "HYST_FMU_LIBRARY";

/// The file name cargo gives the cdylib of crates/hyst-fmu.
const LIBRARY_FILE: &str = "libhyst_fmu.so";

/// The FMU binary built with this `hyst` (a release build: crates/hyst-cli/build.rs), or empty.
const EMBEDDED: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/embedded-fmu.so"));

/// Functions the binary must export (checked by name in its dynamic symbol table's strings):
/// a library without them is not the FMU binary.
const REQUIRED_SYMBOLS: [&str; 6] = [
    "fmi2Instantiate",
    "fmi2DoStep",
    "fmi2GetReal",
    "fmi2SetReal",
    "fmi2GetFMUstate",
    "fmi2DeSerializeFMUstate",
];

/// Finds, reads and checks the FMU binary (see [`LIBRARY_ENV`]).
pub(super) fn read_library() -> Result<Vec<u8>> {
    let build = "build it with `cargo build -p hyst-fmu` (cargo puts libhyst_fmu.so beside \
                 target/debug/hyst), or use a release build of hyst, which holds it";
    let (path, from) = match std::env::var_os(LIBRARY_ENV) {
        Some(p) if !p.is_empty() => (PathBuf::from(p), format!(" (from {LIBRARY_ENV})")),
        _ if !EMBEDDED.is_empty() => {
            check_library(EMBEDDED).context("the FMU binary built into this hyst is not usable")?;
            return Ok(EMBEDDED.to_vec());
        }
        _ => {
            let exe = std::env::current_exe()
                .context("cannot locate the running hyst executable to find the FMU binary")?;
            let dir = exe.parent().unwrap_or(Path::new("."));
            (dir.join(LIBRARY_FILE), String::new())
        }
    };
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) => bail!(
            "the FMU binary {}{from} cannot be read: {e}; {build}, or set {LIBRARY_ENV} to \
             the path of libhyst_fmu.so",
            path.display()
        ),
    };
    check_library(&bytes).with_context(|| {
        format!(
            "the FMU binary {}{from} is not usable; {build}",
            path.display()
        )
    })?;
    Ok(bytes)
}

/// Checks that `bytes` is an x86-64 ELF shared object (what FMI 2.0 calls linux64) that names
/// the FMI 2.0 functions.
fn check_library(bytes: &[u8]) -> Result<()> {
    let u16_at = |i: usize| {
        bytes
            .get(i..i + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
    };
    if bytes.get(..4) != Some(b"\x7fELF".as_slice()) {
        bail!("not an ELF file");
    }
    // EI_CLASS = ELFCLASS64, EI_DATA = little endian, e_type = ET_DYN, e_machine = EM_X86_64.
    if bytes.get(4) != Some(&2) || bytes.get(5) != Some(&1) || u16_at(18) != Some(62) {
        bail!("not a 64-bit x86-64 ELF file (the FMU's platform is linux64)");
    }
    if u16_at(16) != Some(3) {
        bail!("not a shared library");
    }
    for name in REQUIRED_SYMBOLS {
        let mut needle = Vec::with_capacity(name.len() + 2);
        needle.push(0);
        needle.extend_from_slice(name.as_bytes());
        needle.push(0);
        if !bytes.windows(needle.len()).any(|w| w == needle) {
            bail!("it does not export {name}");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
    use super::*;

    #[test]
    fn library_checks() {
        let mut elf = vec![0u8; 64];
        elf[..4].copy_from_slice(b"\x7fELF");
        elf[4] = 2;
        elf[5] = 1;
        elf[16] = 3;
        elf[18] = 62;
        assert!(check_library(&elf)
            .unwrap_err()
            .to_string()
            .contains("fmi2Instantiate"));
        for s in REQUIRED_SYMBOLS {
            elf.push(0);
            elf.extend_from_slice(s.as_bytes());
        }
        elf.push(0);
        check_library(&elf).unwrap();
        let mut exe = elf.clone();
        exe[16] = 2;
        assert!(check_library(&exe).is_err());
        let mut arm = elf.clone();
        arm[18] = 183;
        assert!(check_library(&arm)
            .unwrap_err()
            .to_string()
            .contains("x86-64"));
        assert!(check_library(b"#!/bin/sh\n").is_err());
    }
}
