//! `phosphor info FILE.obj`: what a mesh holds, as the renderer will see it (docs/conventions.md's
//! normal conventions: `vn` as authored, else smoothing groups, else a 60-degree crease).
//! PLY, STL and glTF files are read by extension; `positions` counts the points faces share
//! after welding (an STL stores three per triangle), `vertices` what the renderer draws.

use phosphor_mesh::{MeshFormat, NormalOptions};

use crate::CliError;
use crate::args::InfoArgs;

/// Runs `phosphor info`.
pub fn run(args: &InfoArgs) -> Result<(), CliError> {
    phosphor_args::check_mesh_path(None, &args.mesh).map_err(CliError::Usage)?;
    let (mesh, warnings) =
        phosphor_mesh::load_mesh_with_warnings(&args.mesh, &NormalOptions::default())
            .map_err(|e| CliError::Input(e.to_string()))?;
    for w in warnings {
        phosphor_output::term::warn(&w);
    }
    say!("file:             {}", args.mesh.display());
    say!(
        "format:           {}",
        MeshFormat::from_path(&args.mesh).name()
    );
    say!("{}", mesh.stats());
    say!(
        "groups:           {}",
        if mesh.groups.is_empty() {
            "none".to_owned()
        } else {
            mesh.groups.join(", ")
        }
    );
    say!(
        "texture coords:   {}",
        if mesh.uvs.is_some() { "yes" } else { "no" }
    );
    Ok(())
}
