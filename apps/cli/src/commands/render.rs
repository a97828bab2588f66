//! `phosphor render` (wired to the scene crate once it lands).

use crate::CliError;
use crate::args::*;

/// Runs `phosphor render`.
pub fn run(_args: &RenderArgs) -> Result<(), CliError> {
    Err(CliError::Input("not implemented yet".into()))
}
