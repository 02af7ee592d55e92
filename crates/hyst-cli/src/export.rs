//! `hyst export c|rust MODEL --name NAME -o FILE`: a model file as firmware source, exact from
//! the first sample (the generators are hyst-codegen's, shared with Python's
//! `Model.export_c`/`export_rust`). A model with dynamics adds its compensator, and with
//! `--period SECONDS` its forward model with the plant discretised for that period. Everything
//! is checked before anything is written, and the file is written atomically: on failure no
//! output file exists.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use hyst_codegen::Source;
use hyst_model::ModelFile;

/// Arguments of `hyst export`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to write.
    #[command(subcommand)]
    pub target: Target,
}

/// The languages a model exports to.
#[derive(clap::Subcommand, Debug)]
pub enum Target {
    /// A header-only C99 file over hyst.h: NAME_state, NAME_init, NAME_init_inverse, NAME_step,
    /// NAME_reset, NAME_params and their _f32 twins; for a model with dynamics also
    /// NAME_timed_compensator_* and, with --period, NAME_timed_* (docs/c.md).
    C(Files),
    /// no_std Rust over hyst-core: NAME::<T>(), NAME_inverse::<T>(), NAME_clamp and the model's
    /// types, for embedded Rust; for a model with dynamics also NAME_timed_compensator::<T>()
    /// and, with --period, NAME_timed::<T>() (docs/c.md).
    Rust(Files),
}

/// Arguments of `hyst export c` and `hyst export rust`.
#[derive(clap::Args, Debug)]
pub struct Files {
    /// The model file (`hyst fit -o`).
    pub model: PathBuf,
    /// The prefix of every identifier of the file: a C identifier (letters, digits, `_`), not
    /// starting with `hyst` (hyst.h's own). Default: the model file's name without its
    /// extension, when it is one.
    #[arg(long)]
    pub name: Option<String>,
    /// The file to write (written atomically); `-` or none: standard output.
    #[arg(short = 'o', long = "out", alias = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// For a model with dynamics: the sample period in seconds of the exported model with its
    /// plant (NAME_timed), which is discretised for it here. The records' mean time step (what
    /// `hyst run` takes from their time stamps) gives `hyst run`'s outputs. Unused for a model
    /// without dynamics.
    #[arg(long, value_name = "SECONDS")]
    pub period: Option<f64>,
}

impl Target {
    /// The arguments, whichever language.
    pub fn args(&self) -> &Files {
        match self {
            Target::C(a) | Target::Rust(a) => a,
        }
    }
}

/// Runs `hyst export`.
pub fn main(args: Args) -> Result<()> {
    let a = args.target.args();
    let bytes = std::fs::read(&a.model)
        .with_context(|| format!("hyst export: cannot read {}", a.model.display()))?;
    let text = String::from_utf8(bytes.clone())
        .map_err(|_| anyhow::anyhow!("{}: not a UTF-8 text file", a.model.display()))?;
    let file = ModelFile::from_toml(&text, &a.model)?;
    let name = match &a.name {
        Some(n) => n.clone(),
        None => default_name(&a.model)?,
    };
    let source = Source::of_file(&a.model.display().to_string(), &bytes);
    let options = hyst_codegen::Options { period: a.period };
    let (what, generated) = match &args.target {
        Target::C(_) => ("C", hyst_codegen::c_with(&file, &name, &source, &options)),
        Target::Rust(_) => (
            "Rust",
            hyst_codegen::rust_with(&file, &name, &source, &options),
        ),
    };
    let generated = generated.with_context(|| {
        format!(
            "hyst export: {} cannot be exported as {what}",
            a.model.display()
        )
    })?;
    if let Some(reason) = hyst_codegen::no_float_reason(&file, &options) {
        eprintln!(
            "hyst export: note: no float form ({}): {reason}",
            match &args.target {
                Target::C(_) => "no _f32 twins written",
                Target::Rust(_) => "T = f32 returns Err(InvalidParameter)",
            }
        );
    }
    match &a.output {
        Some(path) if path.as_os_str() != "-" => {
            hyst_io::write_atomic(path, generated.as_bytes())?;
            eprintln!(
                "hyst export: wrote {} ({what}, name {name}, {} lines)",
                path.display(),
                generated.lines().count()
            );
        }
        _ => std::io::stdout()
            .lock()
            .write_all(generated.as_bytes())
            .context("hyst export: cannot write to standard output")?,
    }
    Ok(())
}

/// The model file's name without its extension, when it is a usable name.
fn default_name(model: &Path) -> Result<String> {
    let stem = model
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default()
        .to_string();
    hyst_codegen::check_name(&stem).with_context(|| {
        format!(
            "hyst export: no --name given, and the model file's name {stem:?} cannot be one; \
             give --name NAME"
        )
    })?;
    Ok(stem)
}
