//! One module per subcommand; each exposes `run(&Args) -> Result<(), CliError>`.

pub mod accuracy;
pub mod bench;
pub mod info;
pub mod render;
