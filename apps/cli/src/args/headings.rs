//! Every flag of every subcommand is listed in `--help` under the heading of its concern; the
//! test below walks clap's command tree, so a new flag without a heading (or under another
//! concern's) fails it.

#[cfg(test)]
mod tests {
    use clap::CommandFactory;
    use phosphor_args::{
        CAMERA_HEADING, INPUT_HEADING, NORMALS_HEADING, OUTPUT_HEADING, RENDERING_HEADING,
    };

    use crate::args::{Cli, MEASURING_HEADING, SEQUENCE_HEADING};

    /// The heading each flag belongs under, in `subcommand`.
    fn expected(subcommand: &str, flag: &str) -> Option<&'static str> {
        Some(match flag {
            "mesh" => INPUT_HEADING,
            "eye" | "target" | "up" | "fov" | "azimuth" | "elevation" | "distance" | "ortho"
            | "view" => CAMERA_HEADING,
            "crease_angle"
            | "normals"
            | "weighting"
            | "no_smoothing_groups"
            | "split_by_material" => NORMALS_HEADING,
            "cull" | "aa" | "size" | "threads" | "fast_phong" | "interpolation" | "simd"
            | "shadows" | "background" | "wireframe" | "wire_edges" | "grid" | "axes" => {
                RENDERING_HEADING
            }
            "shading" if subcommand == "bench" => MEASURING_HEADING,
            "shading" => RENDERING_HEADING,
            "output" | "encoding" | "force" | "plan" | "out_dir" | "csv" | "exposure"
            | "tone_map" => OUTPUT_HEADING,
            "turntable" | "time" | "fps" => SEQUENCE_HEADING,
            "frames" if subcommand == "render" => SEQUENCE_HEADING,
            "frames" => MEASURING_HEADING,
            _ => return None,
        })
    }

    #[test]
    fn every_flag_of_every_subcommand_is_under_its_concerns_heading() {
        let cli = Cli::command();
        let mut checked = 0;
        for sub in cli.get_subcommands() {
            for arg in sub.get_arguments() {
                let id = arg.get_id().as_str();
                if arg.is_positional() || matches!(id, "help" | "version") {
                    continue;
                }
                let want = expected(sub.get_name(), id);
                assert!(
                    want.is_some(),
                    "phosphor {} --{id}: no heading expected for it; add it to this test's map",
                    sub.get_name()
                );
                assert_eq!(
                    arg.get_help_heading(),
                    want,
                    "phosphor {} --{id}",
                    sub.get_name()
                );
                checked += 1;
            }
        }
        assert!(checked > 60, "only {checked} flags seen");
    }

    #[test]
    fn render_help_lists_force_under_output_and_aa_under_rendering() {
        let mut cli = Cli::command();
        let help = cli
            .find_subcommand_mut("render")
            .map(|c| c.render_long_help().to_string())
            .unwrap_or_default();
        let section = |flag: &str| {
            let at = help.find(flag).unwrap_or(0);
            help[..at]
                .lines()
                .rfind(|l| !l.starts_with(' ') && l.ends_with(':'))
                .unwrap_or("")
                .to_owned()
        };
        assert_eq!(section("      --force"), "Output:");
        assert_eq!(section("      --exposure "), "Output:");
        assert_eq!(section("      --tone-map "), "Output:");
        assert_eq!(section("      --background "), "Rendering:");
        assert_eq!(section("      --aa "), "Rendering:");
        assert_eq!(section("      --frames "), "Sequences:");
        assert!(section("      --eye ").starts_with("Camera"));
        assert!(section("      --crease-angle ").starts_with("Normals of --mesh"));
    }
}
