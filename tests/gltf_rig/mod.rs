//! A glTF file for the camera tests (`gltf_camera_motion`, `gltf_camera_chain`): a grey quad
//! and a triangle under a white sky, a camera node under a rig node, and the animation channels
//! a test gives; and the direct render of such a file with small settings.
#![allow(dead_code)]

use prism::config::{AnimationConfig, ShutterConfig};
use prism::film::Film;
use std::path::Path;

/// A glTF channel: (node, path, interpolation, key times, outputs).
pub type Channel = (
    u32,
    &'static str,
    &'static str,
    &'static [f32],
    &'static [f32],
);

pub const T01: &[f32] = &[0.0, 1.0];
/// The camera's slide: (0, 0, 4) to (1, 0.5, 4) in its rig, 1 above.
pub const SLIDE: &[f32] = &[0.0, 0.0, 4.0, 1.0, 0.5, 4.0];
/// The same slide, 1 higher: the rig's.
pub const RIG_SLIDE: &[f32] = &[0.0, 0.0, 5.0, 1.0, 0.5, 5.0];
/// A half-turn about y over the second: identity, then (0, 1, 0, 0), both exact in f32.
pub const TURN: &[f32] = &[0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0];

/// A grey quad at z = 0 and a triangle at z = 1 (parallax) under a white sky; node 1, "Rig"
/// (`rig` fields), holds node 2, "Cam" (`cam` fields), a perspective camera (yfov 0.9 rad)
/// looking along its −z; `channels` animate them.
pub fn model(rig: &str, cam: &str, channels: &[Channel]) -> String {
    let mut bytes: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut samplers, mut chans) = (vec![], vec![], vec![], vec![]);
    let mut push = |v: &[f32], ty: &str, n: usize, extra: &str| {
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            bytes.len(),
            v.len() * 4
        ));
        accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": 5126, "count": {n}, "type": "{ty}"{extra}}}"#,
            views.len() - 1
        ));
        v.iter().for_each(|x| bytes.extend(x.to_le_bytes()));
    };
    #[rustfmt::skip]
    let positions = [
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0,
        -1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
        -0.5, -0.5, 1.0, 0.3, -0.5, 1.0, 0.0, 0.4, 1.0,
    ];
    push(
        &positions,
        "VEC3",
        9,
        r#", "min": [-1, -1, 0], "max": [1, 1, 1]"#,
    );
    for (k, (node, path, interp, times, out)) in channels.iter().enumerate() {
        let (ty, width) = if *path == "rotation" {
            ("VEC4", 4)
        } else {
            ("VEC3", 3)
        };
        push(times, "SCALAR", times.len(), "");
        push(out, ty, out.len() / width, "");
        samplers.push(format!(
            r#"{{"input": {}, "output": {}, "interpolation": "{interp}"}}"#,
            1 + 2 * k,
            2 + 2 * k
        ));
        chans.push(format!(
            r#"{{"sampler": {k}, "target": {{"node": {node}, "path": "{path}"}}}}"#
        ));
    }
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0}}, {{"name": "Rig", "children": [2]{rig}}}, {{"name": "Cam", "camera": 0{cam}}}],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.9, "znear": 0.01, "zfar": 100, "aspectRatio": 1.3333}}}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.2, 0.2, 1], "metallicFactor": 0}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
  "animations": [{{"samplers": [{}], "channels": [{}]}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{}], "accessors": [{}]}}"#,
        samplers.join(", "),
        chans.join(", "),
        bytes.len(),
        base64::encode(&bytes),
        views.join(", "),
        accessors.join(", ")
    )
}

/// The render settings the tests use, over the direct render's defaults.
pub fn small(cfg: &mut prism::config::SceneConfig, spp: u32, seed: u64) {
    let s = prism::config::parse_str(
        &format!(
            r#"(film: (width: 24, height: 18, filter: Box()), sampler: (spp: {spp}, seed: {seed}),
            spectral: (sampling: Uniform, range: (500, 600), wavelengths: 1),
            outputs: (rgb: false, xyz: false, bands: 1, band_range: (500, 600)))"#
        ),
        Path::new("settings.ron"),
    )
    .unwrap();
    (cfg.film, cfg.sampler, cfg.spectral, cfg.outputs) = (s.film, s.sampler, s.spectral, s.outputs);
}

pub fn values(film: &Film) -> Vec<f32> {
    film.channel("S0.550,000000nm").expect("the band").to_vec()
}

/// Renders the glTF file `path` directly with `shutter`, and the camera's motion replaced by
/// the RON `animation` if given.
pub fn render(
    path: &Path,
    shutter: ShutterConfig,
    spp: u32,
    seed: u64,
    ron: Option<&AnimationConfig>,
) -> Vec<f32> {
    let job = prism::load::load(path, |cfg| {
        small(cfg, spp, seed);
        cfg.camera.shutter = Some(shutter);
        if let Some(a) = ron {
            cfg.camera.to_world.clear();
            cfg.camera.animation = Some(a.clone());
        }
    })
    .unwrap();
    values(&prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0)
}

/// The blurred render of `p` (shutter [0, 0.2] s) against the mean of renders at 16 instants
/// across it (the midpoint rule), per column: the worst column's difference as a fraction of
/// its tolerance, 5 standard deviations of the noise (estimated from two blurred renders of
/// different seeds) plus 2% of the column for the midpoint rule; and the same fraction for
/// the camera held at mid-shutter (a test of the blur needs it above 1).
pub fn blur_against_instants(p: &Path) -> (f64, f64) {
    let (w, h, spp, k) = (24usize, 18usize, 64u32, 16usize);
    let open = |t0: f32, t1: f32| ShutterConfig {
        open: t0,
        close: t1,
        readout: 0.0,
    };
    let (b1, b2) = (
        render(p, open(0.0, 0.2), spp, 1, None),
        render(p, open(0.0, 0.2), spp, 2, None),
    );
    let mut avg = vec![0.0f64; w * h];
    for i in 0..k {
        let t = 0.2 * (i as f32 + 0.5) / k as f32;
        for (a, v) in avg
            .iter_mut()
            .zip(render(p, open(t, t), 2 * spp / k as u32, 3, None))
        {
            *a += v as f64 / k as f64;
        }
    }
    let still = render(p, open(0.1, 0.1), 2 * spp, 3, None);
    let (mut worst, mut still_worst) = (0.0f64, 0.0f64);
    for x in 0..w {
        let (mut b, mut a, mut s, mut var) = (0.0, 0.0, 0.0, 0.0);
        for y in 0..h {
            let i = y * w + x;
            let (p1, p2) = (b1[i] as f64, b2[i] as f64);
            b += 0.5 * (p1 + p2);
            a += avg[i];
            s += still[i] as f64;
            // E[(p1 − p2)²] = 2σ² for one render; the mean of two has σ²/2; the instants as much.
            var += 2.0 * (p1 - p2).powi(2) / 4.0;
        }
        let tol = 5.0 * var.sqrt() + 0.02 * a;
        worst = worst.max((b - a).abs() / tol);
        still_worst = still_worst.max((s - a).abs() / tol);
    }
    (worst, still_worst)
}
