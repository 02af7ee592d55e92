//! `hyst fit` (being built; see the issue tracker).

/// Arguments of `hyst fit`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `hyst fit`.
pub fn main(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("hyst fit is not available in this build yet")
}
