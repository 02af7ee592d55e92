//! `hyst run` (being built; see the issue tracker).

/// Arguments of `hyst run`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `hyst run`.
pub fn main(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("hyst run is not available in this build yet")
}
