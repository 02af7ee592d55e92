//! `hyst paper` (being built; see the issue tracker).

/// Arguments of `hyst paper`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `hyst paper`.
pub fn main(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("hyst paper is not available in this build yet")
}
