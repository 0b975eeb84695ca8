//! glTF cameras and KHR_lights_punctual lights as prism config entries, and the scene a bare
//! `prism render model.gltf` renders.
//!
//! **Photometric units.** glTF gives point and spot intensities in candela (lm/sr) and
//! directional illuminance in lux (lm/m²). prism's spectra are radiometric per nanometre, so a
//! light of colour c with luminous value I_v becomes
//! I_e(λ) = I_v · S(λ) / (683 lm/W · ∫ S(λ) ȳ(λ) dλ), with S the colour uplifted as an
//! illuminant (Jakob–Hanika sigmoid times D65, as every RGB emission in prism) and the integral
//! over the CIE 1931 ȳ (360–830 nm): the light's luminous intensity (illuminance) computed back
//! from I_e is exactly I_v. `range` is ignored (physical inverse-square falloff).
//!
//! **Cameras.** glTF cameras look along their local −z with +y up and +x right; prism's look
//! along +z with +x left, so the camera's world matrix is composed with diag(−1, 1, −1) (a
//! half-turn about y). `yfov` is the vertical field of view; `aspectRatio` sets the film width
//! (576 pixels high by default). Orthographic cameras become prism's `Orthographic` model,
//! 2·xmag wide, with aspect xmag / ymag.

use super::nodes::walk_with;
use crate::camera::FovAxis;
use crate::config::{
    CameraConfig, CameraModel, EmitterConfig, FilmConfig, SceneConfig, ShapeConfig, ShapeKind,
    SpectrumConfig, TransformOp,
};
use crate::error::InputError;
use crate::math::portable;
use crate::motion::Motion;
use crate::spectrum::color::cie1931;
use crate::spectrum::Curve;
use glam::{Mat4, Vec3, Vec4};
use std::collections::BTreeMap;
use std::path::Path;

/// Lumens per watt at 555 nm (the SI definition of the candela).
pub const LUMINOUS_EFFICACY: f32 = 683.0;

/// A camera found in the node tree.
pub struct GltfCamera {
    pub name: String,
    /// Always present (kept optional for cameras a later glTF version may add).
    pub config: Option<CameraConfig>,
    pub aspect: Option<f32>,
}

/// A KHR_lights_punctual light, as a prism emitter.
pub struct GltfLight {
    pub name: String,
    pub emitter: EmitterConfig,
    /// With an open shutter, under an animated node: the motion carrying `emitter` (then in
    /// that node's frame) to the world, as a RON light's `animation` does
    /// (`emitter::MovingLight`).
    pub motion: Option<Motion>,
}

/// A row-major matrix op (the config's `Matrix`), exact for any Mat4.
pub(super) fn matrix_op(m: Mat4) -> TransformOp {
    TransformOp::Matrix(m.transpose().to_cols_array_2d())
}

pub fn camera(cam: &gltf::Camera, world: Mat4, node_name: Option<&str>) -> GltfCamera {
    let name = cam
        .name()
        .or(node_name)
        .map_or_else(|| format!("camera{}", cam.index()), str::to_owned);
    match cam.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let flip = Mat4::from_diagonal(Vec4::new(-1.0, 1.0, -1.0, 1.0));
            GltfCamera {
                name,
                config: Some(CameraConfig {
                    fov: p.yfov().to_degrees(),
                    fov_axis: FovAxis::Y,
                    near_clip: p.znear(),
                    far_clip: p.zfar().unwrap_or(1e4),
                    to_world: vec![matrix_op(world * flip)],
                    ..CameraConfig::default()
                }),
                aspect: p.aspect_ratio(),
            }
        }
        // xmag and ymag are half the view's width and height.
        gltf::camera::Projection::Orthographic(o) => GltfCamera {
            name,
            config: Some(CameraConfig {
                model: CameraModel::Orthographic {
                    width: Some(2.0 * o.xmag()),
                },
                near_clip: o.znear(),
                far_clip: o.zfar(),
                to_world: vec![matrix_op(
                    world * Mat4::from_diagonal(Vec4::new(-1.0, 1.0, -1.0, 1.0)),
                )],
                ..CameraConfig::default()
            }),
            aspect: Some(o.xmag() / o.ymag()),
        },
    }
}

/// ∫ S ȳ dλ over the CIE table's range (nm · S's unit), midpoint rule at 0.25 nm.
fn luminous_integral(s: &Curve) -> f64 {
    let cmf = cie1931();
    let (lo, hi) = cmf.range();
    let n = ((hi - lo) * 4.0) as usize;
    let h = (hi - lo) as f64 / n as f64;
    (0..n)
        .map(|i| {
            let l = lo + (i as f32 + 0.5) * (hi - lo) / n as f32;
            cmf.eval(l)[1] as f64 * s.eval_one(l) as f64 * h
        })
        .sum()
}

/// The factor k such that k · S(λ) (S the colour uplifted as an emission) carries luminous
/// value `photometric` (candela or lux).
pub fn photometric_scale(color: [f32; 3], photometric: f32) -> f32 {
    let s = Curve::rgb_illuminant(color);
    let y = luminous_integral(&s);
    if y <= 0.0 {
        return 0.0;
    }
    (photometric as f64 / (LUMINOUS_EFFICACY as f64 * y)) as f32
}

/// Light `l` at `world`; under an animated node with an open shutter, `moving` is that node's
/// motion and the transform `below` it (world(t) = motion(t) · below), and the light is placed
/// by `below` and carried by the motion.
pub fn light(
    l: &gltf::khr_lights_punctual::Light,
    world: Mat4,
    moving: Option<(Motion, Mat4)>,
) -> GltfLight {
    use gltf::khr_lights_punctual::Kind;
    let (world, motion) = match moving {
        Some((m, below)) => (below, Some(m)),
        None => (world, None),
    };
    let name = l
        .name()
        .map_or_else(|| format!("light{}", l.index()), str::to_owned);
    let c = l.color();
    let spectrum = SpectrumConfig::Scaled(
        photometric_scale(c, l.intensity()),
        Box::new(SpectrumConfig::Rgb(c[0], c[1], c[2])),
    );
    let emitter = match l.kind() {
        Kind::Point => EmitterConfig::Point {
            position: world.transform_point3(Vec3::ZERO).into(),
            intensity: spectrum,
            animation: None,
        },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => EmitterConfig::Spot {
            intensity: spectrum,
            cutoff_angle: outer_cone_angle.to_degrees().min(90.0),
            beam_width: Some(
                inner_cone_angle
                    .to_degrees()
                    .min(outer_cone_angle.to_degrees())
                    .min(90.0),
            ),
            // glTF spots shine along local −z, prism's along +z: a half-turn about x.
            to_world: vec![matrix_op(
                world * Mat4::from_diagonal(Vec4::new(1.0, -1.0, -1.0, 1.0)),
            )],
            animation: None,
        },
        Kind::Directional => EmitterConfig::Directional {
            irradiance: spectrum,
            direction: Some(
                world
                    .transform_vector3(Vec3::NEG_Z)
                    .normalize_or_zero()
                    .into(),
            ),
            to_world: Vec::new(),
            animation: None,
        },
    };
    GltfLight {
        name,
        emitter,
        motion,
    }
}

/// The scene `prism render model.gltf` renders: the model, its first camera (or one
/// framing it: looking along −z at the centre of its bounding sphere, 40° across the film's
/// shorter side with 5% margin, +y up), its lights; with no lights and no emissive material, a
/// uniform white environment (`Constant(radiance: Named("D65"))`, luminance 1).
pub fn scene_config(path: &Path) -> Result<(SceneConfig, Vec<String>), InputError> {
    scene_for(&super::open(path)?)
}

/// `scene_config` of a model already read (`load::load` hands it on to the build with
/// `with_model`, so the file is read once).
pub fn scene_for(model: &super::Model) -> Result<(SceneConfig, Vec<String>), InputError> {
    let path = model.path.as_path();
    let mut warnings = Vec::new();
    let w = walk_with(model, Mat4::IDENTITY, true, &mut warnings)?;
    let mut cfg = SceneConfig::default();
    let perspective = w.cameras.iter().find(|c| c.config.is_some());
    match perspective {
        Some(c) => {
            cfg.camera = c.config.clone().expect("a camera");
            if let Some(a) = c.aspect.filter(|a| a.is_finite() && *a > 0.0) {
                cfg.film = FilmConfig {
                    width: ((576.0 * a).round() as u32).max(1),
                    height: 576,
                    ..FilmConfig::default()
                };
            }
        }
        None => {
            let (lo, hi) = w.bounds.ok_or_else(|| {
                InputError::new(path, "the scene has no triangles to frame")
                    .field("scenes")
                    .hint("give the file a mesh, or a camera")
            })?;
            let centre = 0.5 * (lo + hi);
            let r = (0.5 * (hi - lo).length()).max(1e-6);
            let fov = 40.0f32;
            let d = 1.05 * r / portable::sin((0.5 * fov).to_radians());
            cfg.camera = CameraConfig {
                fov,
                fov_axis: FovAxis::Smaller,
                near_clip: 1e-3 * d,
                far_clip: 4.0 * (d + r),
                to_world: vec![TransformOp::LookAt {
                    origin: (centre + Vec3::new(0.0, 0.0, d)).into(),
                    target: centre.into(),
                    up: [0.0, 1.0, 0.0],
                }],
                ..CameraConfig::default()
            };
        }
    }
    let file_name = path.file_name().and_then(|f| f.to_str()).ok_or_else(|| {
        InputError::new(path, "the file name is not valid UTF-8")
            .hint("rename the file to a UTF-8 name")
    })?;
    cfg.shapes.push(ShapeConfig {
        shape: ShapeKind::Gltf {
            path: file_name.to_string(),
            materials: BTreeMap::new(),
            lights: true,
            allow_outside: false,
            animation: None,
        },
        material: None,
        emitter: None,
        to_world: Vec::new(),
        animation: None,
        flip_normals: false,
        one_object: false,
        name: None,
        label: None,
        id: None,
    });
    let emissive = w.primitives.iter().any(|p| {
        let m = match p.material {
            Some(i) => model.doc.materials().nth(i),
            None => None,
        };
        m.is_some_and(|m| m.emissive_factor().iter().any(|&c| c > 0.0))
    });
    if w.lights.is_empty() && !emissive {
        cfg.emitters.push(EmitterConfig::Constant {
            radiance: SpectrumConfig::Named("D65".into()),
        });
    }
    Ok((cfg, warnings))
}
