//! `hyst fmu`: the operator H(k1, k2), a fitted model, or the inverse of either, as an FMI 2.0
//! Co-Simulation FMU for linux64 (Simulink's FMU Import block, OpenModelica, FMPy, ...).
//!
//! Contract (docs/fmu.md). This module packs; what goes into the FMU besides the binary
//! (modelDescription.xml with its variables and value references, resources/fmu.toml and the
//! documentation) is written by crates/hyst-fmu (`hyst_fmu::description`), the crate of the
//! binary that reads it:
//! - NAME.fmu is a zip archive holding `modelDescription.xml` (modelName NAME, a fresh GUID,
//!   modelIdentifier `hyst`), `binaries/linux64/hyst.so` (the cdylib of crates/hyst-fmu,
//!   `libhyst_fmu.so`, copied byte for byte), `resources/fmu.toml` (kind, inverse, the GUID and
//!   k1, k2), `resources/model.toml` (with `--model`: the model file, byte for byte) and
//!   `documentation/index.html`.
//! - The binary is the file named by `HYST_FMU_LIBRARY`, else the one a release build of
//!   `hyst` embeds (crates/hyst-cli/build.rs: an installed `hyst` needs nothing beside it), else
//!   `libhyst_fmu.so` beside the running `hyst` (cargo puts both in target/debug).
//! - The inputs are checked before anything is written (k1, k2 by the core, the model file by
//!   hyst-fit, the binary as an x86-64 ELF shared object exporting the FMI 2.0 functions), and the
//!   FMU is written atomically: on failure no output file exists.

use std::io::{Cursor, Write as _};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::source::{Chosen, Source};
use anyhow::{bail, Context, Result};
use hyst_fmu::description::{Description, Kind};
use hyst_fmu::layout::{CONFIG_FILE, MODEL_FILE};
use hyst_fmu::timed::Timing;
use hyst_model::ModelFile;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

mod library;
use library::read_library;

/// Arguments of `hyst fmu`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The operator.
    #[command(flatten)]
    pub source: Source,
    /// With --model --inverse, for a model whose output is bounded by a saturating output or
    /// input shaping (tanh, Langevin): the FMU clamps every desired output beyond the model's
    /// limits (the outputs reachable from every state, within 99.9 % of each saturating
    /// shaping's range: docs/formats.md) to them, as `hyst run --saturate` does, instead of
    /// refusing a value out of reach; fmi2DoStep returns fmi2Warning (and logs it) when the
    /// desired output enters saturation.
    #[arg(long)]
    pub saturate: bool,
    /// The FMU to write (NAME.fmu; NAME becomes the modelName). Written atomically.
    #[arg(short = 'o', long = "out", alias = "output", value_name = "FILE")]
    pub output: PathBuf,
}

/// Runs `hyst fmu`.
pub fn main(args: Args) -> Result<()> {
    let model_name = model_name(&args.output)?;
    let (kind, model) = match args.source.chosen()? {
        Chosen::Model(path) => {
            let (kind, bytes) = read_model(path, &args)?;
            (kind, Some(bytes))
        }
        Chosen::Parameters { k1, k2 } => (Kind::Operator { k1, k2 }, None),
    };
    if args.saturate {
        match &kind {
            Kind::Model { file, .. } if args.source.inverse => {
                if file.saturation().is_none() {
                    bail!(
                        "--saturate: the model's output is unbounded (neither its input nor its \
                         output shaping saturates), so no desired output needs clamping"
                    );
                }
            }
            _ => bail!(
                "--saturate applies to --model FILE --inverse: the inverse of a model whose \
                 output is bounded (a saturating input or output shaping)"
            ),
        }
    }
    let library = read_library()?;
    let (generated, timestamp) = now()?;
    let fmu = Description {
        model_name,
        guid: guid()?,
        generated,
        kind,
        inverse: args.source.inverse,
        saturate: args.saturate,
        command: command_line(),
    };
    let bytes = archive(&fmu, model.as_deref(), &library, timestamp)?;
    hyst_io::write_atomic(&args.output, &bytes)?;
    outln!(
        "wrote {} (FMI 2.0 co-simulation, linux64: {}; guid {})",
        args.output.display(),
        fmu.what(),
        fmu.guid
    );
    Ok(())
}

/// The modelName: the output file's name without `.fmu`.
fn model_name(output: &Path) -> Result<String> {
    let is_fmu = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fmu"));
    let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    if !is_fmu || stem.is_empty() {
        bail!(
            "-o {}: the FMU's file name must be NAME.fmu (tools look for the .fmu extension; \
             NAME becomes the modelName)",
            output.display()
        );
    }
    Ok(stem.to_string())
}

/// Reads and checks the model file, keeping the bytes that were checked (they go into the FMU).
/// What the FMU cannot run (`Timing::of`) is refused here rather than at instantiation.
fn read_model(path: &Path, args: &Args) -> Result<(Kind, Vec<u8>)> {
    let model = ModelFile::read(path)?; // the same checks and messages as `hyst run --model`
    let timing = Timing::of(&model, args.source.inverse, args.saturate)
        .map_err(anyhow::Error::msg)
        .with_context(|| path.display().to_string())?;
    if is_same_file(path, &args.output) {
        bail!(
            "-o {}: that is the model file itself; write the FMU to another file",
            args.output.display()
        );
    }
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let text = std::str::from_utf8(&bytes)
        .with_context(|| format!("{}: not UTF-8 text", path.display()))?;
    let file = ModelFile::from_toml(text, path)?;
    let kind = Kind::Model {
        file: Box::new(file),
        timing,
    };
    Ok((kind, bytes))
}

/// Whether `a` and `b` name the same existing file.
fn is_same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// A fresh GUID, `{8-4-4-4-12}` lowercase hex (a random UUID, version 4).
fn guid() -> Result<String> {
    let mut b = [0u8; 16];
    getrandom::fill(&mut b).map_err(|e| anyhow::anyhow!("cannot draw random bits: {e}"))?;
    b[6] = (b[6] & 0x0f) | 0x40;
    b[8] = (b[8] & 0x3f) | 0x80;
    let hex: String = b.iter().map(|v| format!("{v:02x}")).collect();
    Ok(format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    ))
}

/// The current UTC time as xs:dateTime and as a zip timestamp.
fn now() -> Result<(String, zip::DateTime)> {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .context("the system clock is before 1970")?
        .as_secs();
    let (year, month, day) = civil_from_days((secs / 86_400) as i64);
    let s = secs % 86_400;
    let (hour, minute, second) = (s / 3600, s / 60 % 60, s % 60);
    let text = format!("{year:04}-{month:02}-{day:02}T{hour:02}:{minute:02}:{second:02}Z");
    // Zip timestamps cover 1980..=2107; outside, the zip format's default (1980-01-01).
    let stamp = u16::try_from(year)
        .ok()
        .and_then(|y| {
            zip::DateTime::from_date_and_time(
                y,
                month as u8,
                day as u8,
                hour as u8,
                minute as u8,
                second as u8,
            )
            .ok()
        })
        .unwrap_or_default();
    Ok((text, stamp))
}

/// (year, month, day) of the proleptic Gregorian calendar for a count of days since 1970-01-01
/// (H. Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// The command line, each argument quoted for a POSIX shell where it needs it.
fn command_line() -> String {
    std::env::args_os()
        .enumerate()
        .map(|(i, a)| {
            if i == 0 {
                return "hyst".to_string();
            }
            let a = a.to_string_lossy();
            let plain = !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
            if plain {
                a.into_owned()
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The FMU's bytes (a deflated zip archive): the description, configuration and documentation
/// of `fmu`, the `library` (the binary), and the `model` file's bytes, every entry stamped
/// `timestamp`.
fn archive(
    fmu: &Description,
    model: Option<&[u8]>,
    library: &[u8],
    timestamp: zip::DateTime,
) -> Result<Vec<u8>> {
    let options = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(timestamp);
    let file = options.unix_permissions(0o644);
    let dir = options.unix_permissions(0o755);
    let (config_name, model_name) = (
        format!("resources/{CONFIG_FILE}"),
        format!("resources/{MODEL_FILE}"),
    );
    let mut files: Vec<(&str, Vec<u8>, SimpleFileOptions)> = vec![
        (
            "modelDescription.xml",
            fmu.model_description().into_bytes(),
            file,
        ),
        ("binaries/", Vec::new(), dir),
        ("binaries/linux64/", Vec::new(), dir),
        ("binaries/linux64/hyst.so", library.to_vec(), dir),
        ("resources/", Vec::new(), dir),
        (&config_name, fmu.config().into_bytes(), file),
    ];
    if let Some(bytes) = model {
        files.push((&model_name, bytes.to_vec(), file));
    }
    files.push(("documentation/", Vec::new(), dir));
    files.push((
        "documentation/index.html",
        fmu.documentation().into_bytes(),
        file,
    ));
    let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
    for (name, bytes, options) in files {
        if name.ends_with('/') {
            zip.add_directory(name, options)
        } else {
            zip.start_file(name, options)
        }
        .with_context(|| format!("cannot add {name} to the FMU"))?;
        zip.write_all(&bytes)
            .with_context(|| format!("cannot add {name} to the FMU"))?;
    }
    let cursor = zip
        .finish()
        .context("cannot finish the FMU's zip archive")?;
    Ok(cursor.into_inner())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }

    #[test]
    fn guids_are_fresh_and_well_formed() {
        let a = guid().unwrap();
        let b = guid().unwrap();
        assert_ne!(a, b);
        assert_eq!(a.len(), 38);
        let inner = a.strip_prefix('{').unwrap().strip_suffix('}').unwrap();
        let groups: Vec<usize> = inner.split('-').map(str::len).collect();
        assert_eq!(groups, [8, 4, 4, 4, 12]);
        assert!(inner
            .chars()
            .all(|c| c == '-' || c.is_ascii_digit() || ('a'..='f').contains(&c)));
    }
}
