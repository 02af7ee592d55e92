//! Which operator a command works with (`hyst run`, `hyst fmu`): H(k1, k2) from its parameters
//! or a fitted model file, direct or inverse.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use hyst_core::Hysteresis;

/// The operator's arguments, shared by every command that runs or packs one.
#[derive(clap::Args, Debug)]
pub struct Source {
    /// k1: half-width of the hysteresis loop, in output units (> 0).
    #[arg(long, required_unless_present = "model", allow_negative_numbers = true)]
    pub k1: Option<f64>,
    /// k2: rate of the transition to the asymptotes, in 1/input units (> 0).
    #[arg(long, required_unless_present = "model", allow_negative_numbers = true)]
    pub k2: Option<f64>,
    /// A fitted model file (TOML, see docs/formats.md) instead of --k1/--k2.
    #[arg(long, conflicts_with_all = ["k1", "k2"])]
    pub model: Option<PathBuf>,
    /// The inverse: H⁻¹ (eq. 4), or the model's exact inverse; desired output in, command out.
    #[arg(long)]
    pub inverse: bool,
}

/// What [`Source`] chose.
pub enum Chosen<'a> {
    /// H(k1, k2) (or H⁻¹) with checked parameters.
    Parameters {
        /// k1 > 0.
        k1: f64,
        /// k2 > 0.
        k2: f64,
    },
    /// The model file at this path (read and checked by the command).
    Model(&'a Path),
}

impl Source {
    /// The parameters (checked: finite and > 0, as the core requires) or the model file.
    ///
    /// # Errors
    /// Neither --model nor both --k1 and --k2; an invalid k1 or k2, named with its value.
    pub fn chosen(&self) -> Result<Chosen<'_>> {
        if let Some(path) = &self.model {
            return Ok(Chosen::Model(path));
        }
        let (Some(k1), Some(k2)) = (self.k1, self.k2) else {
            bail!("give --k1 and --k2 (or --model FILE)");
        };
        // The direct and the inverse operator accept the same parameters.
        Hysteresis::new(k1, k2).context("--k1/--k2")?;
        Ok(Chosen::Parameters { k1, k2 })
    }
}
