//! The MTL file's texture maps, read by a line scan of our own.
//!
//! tobj reads the colours (`Ka Kd Ks Ns`) but keeps a map statement's options in its file name
//! and knows neither `norm` nor which statements Phosphor ignores, and one map line without a
//! file makes it drop the whole library. So the map statements are blanked in the text tobj
//! gets ([`for_tobj`]) and read here ([`scan`]): `map_Kd`, `map_Ks` and `norm`, each
//! `[options] file`, the file name being the rest of the line (it may hold spaces) resolved
//! against the MTL file's folder. Options: `-clamp on|off` (on: both axes clamp to the edge),
//! `-bm mult` (the normal map's scale), and read past with their arguments `-blendu`,
//! `-blendv`, `-cc`, `-imfchan`, `-texres`, `-type` (one each), `-boost` (one), `-mm` (two),
//! `-o`, `-s`, `-t` (one to three numbers). A malformed option or a map without a file is a
//! warning naming the file and line; the map is then used without the option, or not at all.
//!
//! Every other statement a material holds is listed in [`MaterialMaps::unused`] (`d`,
//! `map_d`, `bump`, `map_Bump`, `disp`, `refl`, `Ke`, ...), except where it changes nothing:
//! `illum 0`, `1` or `2` (the models Phosphor's shading covers), `d 1`, `Tr 0`, `Ke 0 0 0`,
//! and `Ni` (it only matters for the refraction models, which are listed).

use std::path::Path;

use crate::texture_ref::{TextureRef, TextureSource, Wrap};

/// The texture maps and unused statements of one `newmtl` block.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MaterialMaps {
    /// `map_Kd`.
    pub kd_map: Option<TextureRef>,
    /// `map_Ks`.
    pub ks_map: Option<TextureRef>,
    /// `norm` and its `-bm` scale.
    pub normal_map: Option<(TextureRef, f32)>,
    /// Statements present that Phosphor does not use, once each, in order.
    pub unused: Vec<String>,
}

/// Statements that name a map: blanked for tobj (which fails a whole library on some of them).
const MAP_STATEMENTS: [&str; 14] = [
    "map_Ka", "map_Kd", "map_Ks", "map_Ke", "map_Ns", "map_ns", "map_NS", "map_d", "map_Bump",
    "map_bump", "bump", "norm", "disp", "decal",
];

/// Statements Phosphor reads.
const USED: [&str; 8] = ["newmtl", "Ka", "Kd", "Ks", "Ns", "map_Kd", "map_Ks", "norm"];

/// `text` with the map statements blanked (line numbers kept), for tobj.
pub(crate) fn for_tobj(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let keyword = line.split_whitespace().next().unwrap_or("");
        if !MAP_STATEMENTS.contains(&keyword) {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

/// Whether a statement Phosphor does not read changes nothing as written.
fn neutral(keyword: &str, args: &[&str]) -> bool {
    let numbers: Vec<f32> = args.iter().filter_map(|a| a.parse().ok()).collect();
    match keyword {
        "illum" => matches!(args, ["0" | "1" | "2"]),
        "d" => numbers == [1.0],
        "Tr" => numbers == [0.0],
        "Ke" => !numbers.is_empty() && numbers.iter().all(|&x| x == 0.0),
        "Ni" => true,
        _ => false,
    }
}

/// Reads the maps of every `newmtl` block of `text` (the MTL file `file`, in folder `dir`), in
/// order; problems are pushed onto `warnings` as `FILE:LINE: what`.
pub(crate) fn scan(
    text: &str,
    file: &str,
    dir: &Path,
    warnings: &mut Vec<String>,
) -> Vec<MaterialMaps> {
    let mut out: Vec<MaterialMaps> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let words = words(line);
        let Some(&(_, keyword)) = words.first() else {
            continue;
        };
        if keyword.starts_with('#') {
            continue;
        }
        if keyword == "newmtl" {
            out.push(MaterialMaps::default());
            continue;
        }
        // Statements before the first `newmtl` belong to no material (tobj drops them too).
        let Some(current) = out.last_mut() else {
            continue;
        };
        let at = |what: String| format!("{file}:{}: {keyword}: {what}", i + 1);
        match keyword {
            "map_Kd" | "map_Ks" | "norm" => {
                let Some(map) = parse_map(line, &words[1..], dir, warnings, &at) else {
                    continue;
                };
                match keyword {
                    "map_Kd" => current.kd_map = Some(map.texture),
                    "map_Ks" => current.ks_map = Some(map.texture),
                    _ => current.normal_map = Some((map.texture, map.bump)),
                }
            }
            k if USED.contains(&k) => {}
            k => {
                let args: Vec<&str> = words[1..].iter().map(|&(_, w)| w).collect();
                if !neutral(k, &args) && !current.unused.iter().any(|u| u == k) {
                    current.unused.push(k.to_owned());
                }
            }
        }
    }
    out
}

/// The words of `line` with their byte offsets.
fn words(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices() {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, &line[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &line[s..]));
    }
    out
}

/// A map statement's texture and `-bm` value.
struct Map {
    texture: TextureRef,
    bump: f32,
}

/// Parses `[options] file` (the words after the keyword); `None` when there is no file.
fn parse_map(
    line: &str,
    args: &[(usize, &str)],
    dir: &Path,
    warnings: &mut Vec<String>,
    at: &dyn Fn(String) -> String,
) -> Option<Map> {
    let mut wrap = Wrap::Repeat;
    let mut bump = 1.0_f32;
    let mut k = 0;
    while let Some(&(_, option)) = args.get(k).filter(|(_, w)| w.starts_with('-')) {
        k += 1;
        let value = args.get(k).map(|&(_, w)| w);
        let arity: usize = match option {
            "-clamp" => {
                match value {
                    Some("on") => wrap = Wrap::ClampToEdge,
                    Some("off") => wrap = Wrap::Repeat,
                    Some(v) => warnings.push(at(format!(
                        "-clamp expects on or off, found '{}'; not clamped",
                        clip(v)
                    ))),
                    None => {}
                }
                1
            }
            "-bm" => {
                match value.map(str::parse::<f32>) {
                    Some(Ok(v)) if v.is_finite() => bump = v,
                    Some(_) => warnings.push(at(format!(
                        "-bm expects a number, found '{}'; scale 1",
                        clip(value.unwrap_or(""))
                    ))),
                    None => {}
                }
                1
            }
            "-blendu" | "-blendv" | "-cc" | "-imfchan" | "-texres" | "-type" | "-boost" => 1,
            "-mm" => 2,
            "-o" | "-s" | "-t" => {
                let n = args[k..]
                    .iter()
                    .take(3)
                    .take_while(|(_, w)| w.parse::<f32>().is_ok())
                    .count();
                if n == 0 {
                    warnings.push(at(format!("{option} expects 1 to 3 numbers")));
                }
                n
            }
            other => {
                warnings.push(at(format!("unknown option '{}' read past", clip(other))));
                0
            }
        };
        if k + arity > args.len() {
            warnings.push(at(format!(
                "option {option} without its value; map ignored"
            )));
            return None;
        }
        k += arity;
    }
    let Some(&(start, _)) = args.get(k) else {
        warnings.push(at("no file name; map ignored".to_owned()));
        return None;
    };
    let written = line[start..].trim_end().to_owned();
    Some(Map {
        texture: TextureRef {
            source: TextureSource::File(dir.join(&written)),
            wrap_u: wrap,
            wrap_v: wrap,
            written,
        },
        bump,
    })
}

/// At most 32 characters of user text in a message, control characters escaped.
fn clip(s: &str) -> String {
    crate::sanitize::quote(s, 32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn any_text_scans_without_panicking(
            lines in proptest::collection::vec(
                "(newmtl a|map_Kd|map_Ks|norm|-clamp|-bm|-o|-s|-mm|on|off|1|x|t.png| |\t)*",
                0..8,
            )
        ) {
            let text = lines.join("\n");
            let mut warnings = Vec::new();
            let maps = scan(&text, "p.mtl", Path::new(""), &mut warnings);
            prop_assert!(maps.len() <= lines.len());
            prop_assert_eq!(for_tobj(&text).lines().count(), text.lines().count());
        }
    }

    fn one(text: &str) -> (MaterialMaps, Vec<String>) {
        let mut warnings = Vec::new();
        let mut maps = scan(text, "m.mtl", Path::new("dir"), &mut warnings);
        assert_eq!(maps.len(), 1);
        (maps.remove(0), warnings)
    }

    #[test]
    fn options_are_read_past_by_their_arity_and_names_keep_spaces() {
        let (m, w) = one("newmtl a\nmap_Kd -s 1 1 1 -o 0 0 0 -mm 0 1 -bm 2 my tex.png  \n");
        assert!(w.is_empty(), "{w:?}");
        let kd = m.kd_map.expect("map");
        assert_eq!(kd.written, "my tex.png");
        assert_eq!(
            kd.source,
            TextureSource::File(Path::new("dir/my tex.png").into())
        );
        assert_eq!(kd.wrap_u, Wrap::Repeat);
        let (m, _) = one("newmtl a\nmap_Kd -o 0.5 -clamp on t.png\nnorm -bm 0.25 n.png\n");
        assert_eq!(m.kd_map.expect("map").wrap_v, Wrap::ClampToEdge);
        let (n, scale) = m.normal_map.expect("norm");
        assert_eq!((n.written.as_str(), scale), ("n.png", 0.25));
    }

    #[test]
    fn bad_options_and_missing_files_are_warnings_with_the_line() {
        let (m, w) =
            one("newmtl a\nmap_Kd -clamp maybe t.png\nmap_Ks\nnorm -bm\nmap_Kd -zz t2.png\n");
        assert_eq!(
            m.kd_map.as_ref().map(|t| t.written.as_str()),
            Some("t2.png")
        );
        assert!(m.ks_map.is_none() && m.normal_map.is_none());
        assert!(
            w[0].starts_with("m.mtl:2: map_Kd: -clamp expects on or off"),
            "{w:?}"
        );
        assert!(w[1].starts_with("m.mtl:3: map_Ks: no file name"), "{w:?}");
        assert!(
            w[2].starts_with("m.mtl:4: norm: option -bm without its value"),
            "{w:?}"
        );
        assert!(
            w[3].starts_with("m.mtl:5: map_Kd: unknown option '-zz'"),
            "{w:?}"
        );
    }

    #[test]
    fn unused_statements_are_listed_once_and_neutral_ones_not_at_all() {
        let (m, _) = one(
            "newmtl a\nKd 1 1 1\nillum 2\nd 1\nNi 1.5\nKe 0 0 0\nd 0.5\nmap_d a.png\n\
             bump b.png\nd 0.2\nillum 7\n",
        );
        assert_eq!(m.unused, ["d", "map_d", "bump", "illum"]);
    }

    #[test]
    fn map_statements_are_blanked_for_tobj_keeping_lines() {
        assert_eq!(
            for_tobj("newmtl a\nmap_Kd\nKd 1 0 0\nbump x\n"),
            "newmtl a\n\nKd 1 0 0\n\n"
        );
    }
}
