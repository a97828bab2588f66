//! `phosphor info FILE.obj`: what a mesh holds, as the renderer will see it (DESIGN.md's
//! normal conventions: `vn` as authored, else smoothing groups, else a 60-degree crease).

use phosphor_mesh::NormalOptions;

use crate::CliError;
use crate::args::InfoArgs;

/// Runs `phosphor info`.
pub fn run(args: &InfoArgs) -> Result<(), CliError> {
    let (mesh, warnings) =
        phosphor_mesh::load_obj_with_warnings(&args.mesh, &NormalOptions::default())
            .map_err(|e| CliError::Input(e.to_string()))?;
    for w in warnings {
        phosphor_output::term::warn(&w);
    }
    say!("file:             {}", args.mesh.display());
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
