//! `hyst bench` (being built; see the issue tracker).

/// Arguments of `hyst bench`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `hyst bench`.
pub fn main(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("hyst bench is not available in this build yet")
}
