//! `hyst bound` (being built; see the issue tracker).

/// Arguments of `hyst bound`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `hyst bound`.
pub fn main(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("hyst bound is not available in this build yet")
}
