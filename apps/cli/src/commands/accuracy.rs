//! `phosphor accuracy` (wired to the scene crate once it lands).

use crate::CliError;
use crate::args::*;

/// Runs `phosphor accuracy`.
pub fn run(_args: &AccuracyArgs) -> Result<(), CliError> {
    Err(CliError::Input("not implemented yet".into()))
}
