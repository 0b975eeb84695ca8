//! `--export-frame i`: frame i's resolved scene as a RON scene file that `prism render`
//! reproduces from anywhere (every file path made absolute).

use crate::config::{
    Emission, Field, FloatConfig, FloatTextureConfig, IorConfig, IorForm, MaterialConfig,
    SceneConfig, ShapeKind, SpectrumConfig,
};
use ron::extensions::Extensions;
use std::path::Path;

/// The scene as RON text, with its relative paths resolved against `dir`.
pub fn scene_ron(cfg: SceneConfig, dir: &Path) -> Result<String, String> {
    let pretty = ron::ser::PrettyConfig::default().extensions(Extensions::IMPLICIT_SOME);
    ron::ser::to_string_pretty(&rebase(cfg, dir), pretty).map_err(|e| e.to_string())
}

/// The scene with every relative file path resolved against `dir`.
pub fn rebase(mut cfg: SceneConfig, dir: &Path) -> SceneConfig {
    let abs = |p: &mut String| *p = super::plan::absolute(&dir.join(&*p));
    for s in &mut cfg.shapes {
        if let ShapeKind::Mesh { path } | ShapeKind::Gltf { path, .. } = &mut s.shape {
            abs(path);
        }
        if let Some(e) = &mut s.emitter {
            spectrum(&mut e.radiance, &abs);
        }
    }
    for m in cfg.materials.values_mut() {
        material(m, &abs);
    }
    for e in &mut cfg.emitters {
        if let Some(file) = e.file_mut() {
            abs(file);
        }
        if let Emission::Spectrum(s) = e.emission_mut() {
            spectrum(s, &abs);
        }
    }
    cfg
}

fn spectrum(s: &mut SpectrumConfig, abs: &impl Fn(&mut String)) {
    match s {
        SpectrumConfig::File { path, .. } | SpectrumConfig::Bitmap { path, .. } => abs(path),
        SpectrumConfig::Scaled(_, inner) | SpectrumConfig::ColourSpace(_, inner) => {
            spectrum(inner, abs)
        }
        SpectrumConfig::Checkerboard { color0, color1, .. } => {
            spectrum(color0, abs);
            spectrum(color1, abs);
        }
        _ => {}
    }
}

fn float(f: &mut FloatConfig, abs: &impl Fn(&mut String)) {
    if let FloatConfig::Texture(FloatTextureConfig::Bitmap { path, .. }) = f {
        abs(path);
    }
}

fn ior(i: &mut IorConfig, abs: &impl Fn(&mut String)) {
    if let IorConfig::Form(IorForm::Spectrum(s)) = i {
        spectrum(s, abs);
    }
}

fn material(m: &mut MaterialConfig, abs: &impl Fn(&mut String)) {
    m.for_each_field(&mut |f| match f {
        Field::Spectrum(s) => spectrum(s, abs),
        Field::Float(x) => float(x, abs),
        Field::Ior(n) => ior(n, abs),
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every scene in scenes/ survives a trip through the exported RON unchanged (but for its
    /// now absolute paths), so an exported frame renders what the dataset rendered.
    #[test]
    fn scenes_round_trip() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let mut n = 0;
        let dirs = ["", "materials", "stress", "bench"].map(|d| root.join(d));
        let files = dirs.iter().flat_map(|d| std::fs::read_dir(d).unwrap());
        for entry in files {
            let p = entry.unwrap().path();
            if p.extension().is_some_and(|e| e == "ron") {
                let cfg = crate::config::parse_file(&p).unwrap();
                let dir = p.parent().unwrap();
                let text = scene_ron(cfg.clone(), dir).unwrap();
                let back = crate::config::parse_str(&text, &p).unwrap();
                assert_eq!(back, rebase(cfg.clone(), dir), "{}", p.display());
                // Exporting again from anywhere leaves absolute paths alone.
                let again = scene_ron(back.clone(), Path::new("/elsewhere")).unwrap();
                assert_eq!(text, again, "{}", p.display());
                n += 1;
            }
        }
        assert!(n >= 20, "only {n} scenes");
    }
}
