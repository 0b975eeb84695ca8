//! The RGB space of an input value, texture or envmap, by name (`ColourSpace("acescg", …)`,
//! an envmap's `colour_space: "acescg"`); see `spectrum::gamut`.

use super::spectrum::Context;
use crate::error::InputError;
use crate::spectrum::gamut::{gamut_names, Gamut};
use std::path::Path;

/// The space named `name`, or an error listing the valid names.
pub fn gamut(ctx: &Context, name: &str) -> Result<Gamut, InputError> {
    by_name(ctx.file, ctx.field, name)
}

/// [`gamut`] for a field outside a spectrum (an envmap's `colour_space`).
pub fn by_name(file: &Path, field: &str, name: &str) -> Result<Gamut, InputError> {
    Gamut::from_name(name).ok_or_else(|| {
        InputError::new(file, format!("unknown RGB colour space `{name}`"))
            .field(field)
            .hint(format!(
                "the input colour spaces are: {} (linear RGB; sRGB is the default)",
                gamut_names().join(", ")
            ))
    })
}

#[cfg(test)]
mod tests {
    use crate::load::load_str;
    use std::path::Path;

    fn scene(material: &str, emitter: &str, range: (u32, u32)) -> String {
        format!(
            "(film: (width: 2, height: 2), spectral: (range: ({}, {}), sampling: Uniform),
              outputs: (bands: 0), materials: {{\"m\": {material}}},
              shapes: [(shape: Sphere(center: (0, 0, -3), radius: 1), material: \"m\")],
              emitters: [{emitter}])",
            range.0, range.1
        )
    }

    fn load(text: &str) -> Result<Vec<String>, String> {
        match load_str(text, Path::new("t.ron")) {
            Ok(job) => Ok(job.warnings),
            Err(e) => Err(format!("{e} [exit {}]", e.exit_code())),
        }
    }

    const D65: &str = "Constant(radiance: Named(\"D65\"))";

    /// Every space by name, for reflectances and emitters; sRGB written as `Rgb` alone.
    #[test]
    fn colour_spaces_by_name() {
        for name in ["srgb", "rec2020", "display_p3", "ACEScg"] {
            let m = format!("Diffuse(reflectance: ColourSpace(\"{name}\", Rgb(0.7, 0.4, 0.2)))");
            let e =
                format!("Constant(radiance: Scaled(2, ColourSpace(\"{name}\", Rgb(1, 0.5, 0.2))))");
            assert_eq!(load(&scene(&m, &e, (360, 830))), Ok(vec![]), "{name}");
        }
    }

    /// Unknown names list the valid ones (exit 2, naming the field); ColourSpace wraps only RGB
    /// values and bitmaps; a reflectance above 1 is refused in every space.
    #[test]
    fn bad_colour_spaces() {
        let cases = [
            (
                "Diffuse(reflectance: ColourSpace(\"aces\", Rgb(0.5, 0.5, 0.5)))",
                D65,
                "unknown RGB colour space `aces`",
            ),
            (
                "Diffuse(reflectance: ColourSpace(\"rec2020\", Constant(0.5)))",
                D65,
                "wraps an Rgb value or a Bitmap",
            ),
            (
                "Diffuse(reflectance: ColourSpace(\"acescg\", Rgb(1.5, 0.5, 0.5)))",
                D65,
                "must lie in [0, 1]",
            ),
            (
                "Diffuse()",
                "Constant(radiance: ColourSpace(\"p3\", Rgb(1, 1, 1)))",
                "unknown RGB colour space `p3`",
            ),
            (
                "Diffuse()",
                "Envmap(filename: \"sky.exr\", colour_space: \"xyz\")",
                "unknown RGB colour space `xyz`",
            ),
        ];
        for (m, e, want) in cases {
            let err = load(&scene(m, e, (360, 830))).unwrap_err();
            assert!(err.contains(want), "{err}");
            assert!(err.contains("[exit 2]"), "{err}");
            if want.starts_with("unknown") {
                assert!(err.contains("srgb, rec2020, display_p3, acescg"), "{err}");
            }
        }
    }

    /// A render over 300–1100 nm: the NIR metal data (McPeak et al. 2015, 300–1700 nm) give
    /// no warning; the visible-only set of the same metal warns, naming the spectrum, its range
    /// and the set that covers the render's.
    #[test]
    fn nir_metals_cover_a_300_to_1100_render() {
        for m in ["Au_mcpeak", "Ag_mcpeak", "Cu_mcpeak", "Al_mcpeak"] {
            let mat = format!("Conductor(material: \"{m}\")");
            let e = "Constant(radiance: Blackbody(3000))";
            assert_eq!(load(&scene(&mat, e, (300, 1100))), Ok(vec![]), "{m}");
        }
        let e = "Constant(radiance: Blackbody(3000))";
        let w = load(&scene("Conductor(material: \"Au\")", e, (300, 1100))).unwrap();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("`Au` cover 298.757–") && w[0].contains("`Au_mcpeak` (300–1700 nm)"),
            "{w:?}"
        );
    }
}
