//! Reliability (issue 14): no input crashes prism or destroys a file. Regression tests for the
//! defects found by hand with hostile inputs; most run the `prism` binary on a tiny scene
//! (16×12 or smaller, 1-4 spp) so that the whole file takes seconds. docs/reliability.md
//! describes what each class of input gets.

use glam::{Vec2, Vec3};
use prism::bsdf::{BsdfLike, Material};
use prism::interaction::SurfaceInteraction;
use prism::math::Frame;
use prism::spectrum::{WavelengthSampler, WavelengthSampling};
use prism::texture::{FloatTexture, Grid, TexFilter, UvMap, Wrap};
use std::path::Path;

fn material(cfg: &str) -> Material {
    let text = format!(
        "(film: (width: 2, height: 2), outputs: (bands: 0), materials: {{ \"m\": {cfg} }}, shapes: [(shape: Rectangle, material: \"m\")])"
    );
    let job = prism::scene::load_str(&text, Path::new("inline.ron"))
        .unwrap_or_else(|e| panic!("{cfg}: {e}"));
    job.scene.materials[0].clone()
}

/// A 2×2 bitmap with one NaN texel: bilinear lookups anywhere near it are NaN.
fn nan_bitmap() -> FloatTexture {
    FloatTexture::Bitmap(Box::new(Grid {
        width: 2,
        height: 2,
        texels: vec![0.5, f32::NAN, 0.5, 0.5],
        wrap: Wrap::Repeat,
        filter: TexFilter::Bilinear,
        map: UvMap {
            scale: Vec2::ONE,
            offset: Vec2::ZERO,
        },
        source: None,
    }))
}

/// Issue 14 item 1: a NaN opacity or blend weight (a NaN texel) made the mixture empty and
/// `Mixture::sample` indexed past its end (exit 101). Now such a weight counts as 0.
#[test]
fn nan_mask_opacity_and_blend_weight_do_not_panic() {
    let diffuse = material("Diffuse(reflectance: Constant(0.5))");
    let cases = [
        (
            "mask, NaN bitmap",
            Material::Mask {
                inner: Box::new(diffuse.clone()),
                opacity: nan_bitmap(),
            },
        ),
        (
            "mask, NaN constant",
            Material::Mask {
                inner: Box::new(diffuse.clone()),
                opacity: FloatTexture::Constant(f32::NAN),
            },
        ),
        (
            "blend, NaN bitmap",
            Material::Blend {
                a: Box::new(diffuse.clone()),
                b: Box::new(material("RoughConductor(alpha: 0.3)")),
                weight: nan_bitmap(),
            },
        ),
    ];
    let si = SurfaceInteraction {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::from_normal(Vec3::Z),
        uv: Vec2::new(0.5, 0.5),
        t: 1.0,
        shape: 0,
        prim: 0,
    };
    let wl = WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0).sample::<4>(0.37);
    let wi = Vec3::new(0.3, 0.1, 0.9).normalize();
    for (name, m) in &cases {
        let b = m.bsdf(&si, wi, &wl);
        for k in 0..16 {
            let uc = k as f32 / 16.0;
            if let Some(s) = b.sample(wi, uc, Vec2::new(0.3, uc)) {
                assert!(
                    s.weight.0.iter().all(|w| w.is_finite()),
                    "{name}: non-finite weight"
                );
            }
        }
        let f = b.eval(wi, Vec3::new(-0.2, 0.1, 0.97).normalize());
        assert!(f.0.iter().all(|v| v.is_finite()), "{name}: eval {f:?}");
    }
}
