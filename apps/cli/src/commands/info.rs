//! `phosphor info` (wired to the scene crate once it lands).

use crate::CliError;
use crate::args::*;

/// Runs `phosphor info`.
pub fn run(_args: &InfoArgs) -> Result<(), CliError> {
    Err(CliError::Input("not implemented yet".into()))
}
