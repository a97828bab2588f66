//! `phosphor bench` (wired to the scene crate once it lands).

use crate::CliError;
use crate::args::*;

/// Runs `phosphor bench`.
pub fn run(_args: &BenchArgs) -> Result<(), CliError> {
    Err(CliError::Input("not implemented yet".into()))
}
