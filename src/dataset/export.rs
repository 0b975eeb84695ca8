//! `--export-frame i`: frame i's resolved scene as a RON scene file that `prism render`
//! reproduces from anywhere (every file path made absolute).

use crate::config::{
    EmitterConfig, FloatConfig, FloatTextureConfig, IorConfig, IorForm, MaterialConfig,
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
        match e {
            EmitterConfig::Envmap { filename, .. } => abs(filename),
            EmitterConfig::Point { intensity, .. } | EmitterConfig::Spot { intensity, .. } => {
                spectrum(intensity, &abs)
            }
            EmitterConfig::Constant { radiance } => spectrum(radiance, &abs),
            EmitterConfig::Directional { irradiance, .. } => spectrum(irradiance, &abs),
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
    use MaterialConfig as M;
    match m {
        M::Diffuse { reflectance } => spectrum(reflectance, abs),
        M::Twosided { bsdf, back } => {
            material(bsdf, abs);
            if let Some(b) = back {
                material(b, abs);
            }
        }
        M::Blend {
            weight,
            bsdf0,
            bsdf1,
        } => {
            float(weight, abs);
            material(bsdf0, abs);
            material(bsdf1, abs);
        }
        M::Mask { opacity, bsdf } => {
            float(opacity, abs);
            material(bsdf, abs);
        }
        M::Conductor {
            eta,
            k,
            specular_reflectance,
            ..
        } => {
            for s in [eta, k].into_iter().flatten() {
                spectrum(s, abs);
            }
            spectrum(specular_reflectance, abs);
        }
        M::RoughConductor {
            alpha,
            alpha_u,
            alpha_v,
            eta,
            k,
            specular_reflectance,
            ..
        } => {
            for f in [alpha, alpha_u, alpha_v].into_iter().flatten() {
                float(f, abs);
            }
            for s in [eta, k].into_iter().flatten() {
                spectrum(s, abs);
            }
            spectrum(specular_reflectance, abs);
        }
        M::Dielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        }
        | M::ThinDielectric {
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
        } => {
            ior(int_ior, abs);
            ior(ext_ior, abs);
            spectrum(specular_reflectance, abs);
            spectrum(specular_transmittance, abs);
        }
        M::RoughDielectric {
            alpha,
            alpha_u,
            alpha_v,
            int_ior,
            ext_ior,
            specular_reflectance,
            specular_transmittance,
            ..
        } => {
            for f in [alpha, alpha_u, alpha_v].into_iter().flatten() {
                float(f, abs);
            }
            ior(int_ior, abs);
            ior(ext_ior, abs);
            spectrum(specular_reflectance, abs);
            spectrum(specular_transmittance, abs);
        }
        M::Plastic {
            diffuse_reflectance,
            specular_reflectance,
            ..
        }
        | M::RoughPlastic {
            diffuse_reflectance,
            specular_reflectance,
            ..
        } => {
            spectrum(diffuse_reflectance, abs);
            spectrum(specular_reflectance, abs);
        }
        M::Principled {
            base_color,
            metallic,
            roughness,
            specular_color,
            transmission,
            ..
        } => {
            spectrum(base_color, abs);
            spectrum(specular_color, abs);
            for f in [metallic, roughness, transmission] {
                float(f, abs);
            }
        }
    }
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
