//! Textured area lights (RON `emitter: (radiance: Bitmap(..))`, glTF emissiveTexture):
//!
//! - seen directly, every pixel inside one texel shows that texel's RGB (× the scale), as
//!   CIE XYZ through the IEC 61966-2-1 sRGB matrix (a known answer independent of the uplift
//!   code: an illuminant-uplifted RGB reproduces its RGB under D65); black texels give exactly 0;
//! - a glTF emissiveTexture (sRGB PNG × emissiveFactor × emissive strength, read through
//!   TEXCOORD_1 chosen by KHR_texture_transform's texCoord, offset by it) renders its pattern
//!   where the file's uvs put it, and the old "not supported" warning is gone;
//! - irradiance at points below a textured light, estimated by emitter sampling alone
//!   (`sample_li`) and by cosine-weighted direction sampling alone (rays that hit the light,
//!   radiance looked up at the hit's uv), both match the irradiance integrated in the test over
//!   the texels (midpoint rule), and `pdf_li` at the hit equals the sampled density;
//! - the weighted triangle sampler: a chi-square test of sampled points (per triangle and per
//!   quarter of it) against the density `pdf_li` reports, triangles that emit nothing get no
//!   sample and zero density.
//!
//! Tolerances are stated at each test.

mod scratch;
use glam::{Vec2, Vec3};
use prism::emitter::{AreaEmitter, AreaRadiance, EmissionTexture, Emitter};
use prism::interaction::SurfaceInteraction;
use prism::math::portable;
use prism::math::rng::Pcg32;
use prism::math::Frame;
use prism::shape::{Mesh, Shape};
use prism::spectrum::Wavelengths;
use prism::texture::{RgbImage, TexFilter, UvMap, Wrap};
use std::path::{Path, PathBuf};

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("emistex", name)
}

/// Linear sRGB → CIE XYZ (IEC 61966-2-1).
fn srgb_to_xyz(c: [f64; 3]) -> [f64; 3] {
    [
        0.412_456_4 * c[0] + 0.357_576_1 * c[1] + 0.180_437_5 * c[2],
        0.212_672_9 * c[0] + 0.715_152_2 * c[1] + 0.072_175_0 * c[2],
        0.019_333_9 * c[0] + 0.119_192_0 * c[1] + 0.950_304_1 * c[2],
    ]
}

/// The sRGB decoding (IEC 61966-2-1).
fn srgb_decode(v: f64) -> f64 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        portable::powf((v + 0.055) / 1.055, 2.4)
    }
}

/// Renders `job` with per-pixel standard errors; returns (X, Y, Z) means and their standard
/// errors, pixel by pixel.
fn render_xyz(job: &prism::load::Job) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let (film, _, se) =
        prism::integrator::render_film(&job.scene, &job.settings, &job.channels, true, &|_| {});
    let slots = job.channels.sensor.slots();
    let ch = |c: &str| film.channel(c).expect("xyz channels").to_vec();
    let (x, y, z) = (ch("X"), ch("Y"), ch("Z"));
    let means = (0..x.len())
        .map(|i| [x[i] as f64, y[i] as f64, z[i] as f64])
        .collect();
    let errs = (0..x.len())
        .map(|i| [0, 1, 2].map(|k| se.stderr[i * slots + k] as f64))
        .collect();
    (means, errs)
}

/// For each pixel: the world points where the rays through its centre and its four corners hit
/// the scene (None where one misses).
fn pixel_hits(job: &prism::load::Job) -> Vec<Option<[Vec3; 5]>> {
    let (w, h) = (job.settings.width, job.settings.height);
    let mut sampler = prism::sampler::PixelSampler::new(job.settings.sampler, 0, 0);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            // The box filter's samples stay within the pixel's square.
            let pts = [(0.5, 0.5), (0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
            let hits: Option<Vec<Vec3>> = pts
                .iter()
                .map(|&(dx, dy)| {
                    let ray = job
                        .scene
                        .camera
                        .ray(Vec2::new(x as f32 + dx, y as f32 + dy), &mut sampler);
                    job.scene.intersect(&ray).map(|si| si.p)
                })
                .collect();
            out.push(hits.map(|v| [v[0], v[1], v[2], v[3], v[4]]));
        }
    }
    out
}

/// Checks each pixel whose centre and corners all fall in one texel (`texel_of` a world point)
/// against that texel's expected linear RGB; returns how many were checked.
/// Tolerance per channel: 5 standard errors of the pixel (wavelength and position sampling
/// noise) + 1% of the value + 1e-6 (the sigmoid uplift reproduces an RGB under D65 to ~0.1–0.5%
/// (its table's fit), and prism's 1-nm CIE table and D65 give a white point a few 1e-4 off the
/// matrix's).
fn check_texels(
    job: &prism::load::Job,
    texel_of: impl Fn(Vec3) -> Option<usize>,
    rgb: &[[f64; 3]],
) -> usize {
    let (means, errs) = render_xyz(job);
    let hits = pixel_hits(job);
    let mut checked = 0;
    let mut worst = 0.0f64;
    for (i, h) in hits.iter().enumerate() {
        let Some(h) = h else { continue };
        let Some(t) = texel_of(h[0]) else { continue };
        if h[1..].iter().any(|&p| texel_of(p) != Some(t)) {
            continue;
        }
        let want = srgb_to_xyz(rgb[t]);
        for (k, &want_k) in want.iter().enumerate() {
            let (got, se) = (means[i][k], errs[i][k]);
            let tol = 5.0 * se + 0.01 * want_k + 1e-6;
            worst = worst.max((got - want_k).abs() / want_k.max(1e-9));
            assert!(
                (got - want_k).abs() <= tol,
                "pixel {i} (texel {t}), channel {k}: {got} vs {want_k} (se {se})"
            );
            if rgb[t] == [0.0; 3] {
                assert_eq!(got, 0.0, "a black texel emits nothing (pixel {i})");
            }
        }
        checked += 1;
    }
    eprintln!("{checked} pixels checked; largest relative deviation {worst:.4}");
    checked
}

/// RON: a Rectangle light with a 4 × 2 EXR texture (nearest, clamp) times `Scaled(2, ..)`,
/// filling most of the view of a camera straight in front of it; `max_depth: 1`.
#[test]
fn ron_bitmap_light_seen_directly_shows_its_texels() {
    let dir = workdir("ron");
    let texels: [[f32; 3]; 8] = [
        [1.0, 0.2, 0.1],
        [0.1, 0.8, 0.3],
        [0.0, 0.0, 0.0],
        [0.3, 0.3, 1.2],
        [0.5, 0.5, 0.5],
        [2.0, 1.0, 0.0],
        [0.05, 0.02, 0.4],
        [0.9, 0.9, 0.1],
    ];
    exr::prelude::write_rgb_file(dir.join("e.exr"), 4, 2, |x, y| {
        let t = texels[y * 4 + x];
        (t[0], t[1], t[2])
    })
    .unwrap();
    let text = r#"(
        camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
        film: (width: 48, height: 32, filter: Box()),
        sampler: (kind: Independent, spp: 16),
        spectral: (wavelengths: 8),
        integrator: (max_depth: 1),
        outputs: (bands: 0),
        shapes: [(shape: Rectangle, emitter: (radiance: Scaled(2, Bitmap(path: "e.exr", filter: Nearest, wrap: Clamp))))],
    )"#;
    let file = dir.join("scene.ron");
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, |_| {}).unwrap();
    assert!(matches!(
        &job.scene.emitters[0],
        Emitter::Area(a) if matches!(a.radiance, AreaRadiance::Textured(_))
    ));
    // Rectangle: uv = ((x + 1)/2, (y + 1)/2); texture row 0 (the image's top) at v < ½.
    let texel_of = |p: Vec3| {
        let (u, v) = ((p.x + 1.0) / 2.0, (p.y + 1.0) / 2.0);
        ((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v))
            .then(|| (v * 2.0) as usize * 4 + (u * 4.0) as usize)
    };
    let rgb: Vec<[f64; 3]> = texels.iter().map(|t| t.map(|c| 2.0 * c as f64)).collect();
    let n = check_texels(&job, texel_of, &rgb);
    assert!(n > 300, "only {n} pixels inside single texels");
}

/// A textured RON light on a sphere is refused at load, naming the field.
#[test]
fn textured_sphere_light_is_refused() {
    let dir = workdir("sphere");
    image::RgbImage::from_raw(1, 1, vec![255, 255, 255])
        .unwrap()
        .save(dir.join("w.png"))
        .unwrap();
    let text = r#"(shapes: [(shape: Sphere(), emitter: (radiance: Bitmap(path: "w.png")))], outputs: (bands: 0))"#;
    let err = prism::load::load_str(text, &dir.join("s.ron"))
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains("shapes[0].emitter.radiance") && err.contains("triangle mesh"),
        "{err}"
    );
}

/// An HDR light texture with a negative or NaN texel is refused at load, naming the field, the
/// texel and its value (radiance is unbounded above but never negative).
#[test]
fn negative_and_nan_light_texels_are_refused() {
    let dir = workdir("bad_texels");
    for (name, bad) in [("neg.exr", -0.5f32), ("nan.exr", f32::NAN)] {
        exr::prelude::write_rgb_file(dir.join(name), 3, 2, |x, y| {
            if (x, y) == (2, 1) {
                (0.5, bad, 0.5)
            } else {
                (1.0, 1.0, 1.0)
            }
        })
        .unwrap();
        let text = format!(
            r#"(shapes: [(shape: Rectangle, emitter: (radiance: Bitmap(path: "{name}")))], outputs: (bands: 0))"#
        );
        let err = prism::load::load_str(&text, &dir.join("s.ron"))
            .err()
            .expect("refused")
            .to_string();
        assert!(
            err.contains("shapes[0].emitter.radiance")
                && err.contains("texel (2, 1) has G = ")
                && err.contains("an emitted radiance must be finite and ≥ 0"),
            "{err}"
        );
    }
}

/// A unit quad in z = 0 facing +z with TEXCOORD_0 = (x, 1 − y) and TEXCOORD_1 = (1 − x, y),
/// an emissive material reading a 2 × 2 PNG through TEXCOORD_1 (KHR_texture_transform's
/// texCoord overriding the textureInfo's 0) offset by (0.5, 0), NEAREST, REPEAT.
/// `nodes`: the JSON of the node list (all in the scene), each naming mesh 0.
fn emissive_quad(
    dir: &Path,
    texels: &[[u8; 3]; 4],
    factor: [f32; 3],
    strength: f32,
    nodes: &[&str],
) -> PathBuf {
    image::RgbImage::from_raw(2, 2, texels.concat())
        .unwrap()
        .save(dir.join("glow.png"))
        .unwrap();
    let corners = [
        [0.0f32, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [0.0, 0.0],
    ];
    let mut bytes = Vec::new();
    let mut push = |v: &[f32]| {
        v.iter()
            .for_each(|x| bytes.extend_from_slice(&x.to_le_bytes()))
    };
    for c in corners {
        push(&[c[0], c[1], 0.0]);
    }
    for _ in corners {
        push(&[0.0, 0.0, 1.0]);
    }
    for c in corners {
        push(&[c[0], 1.0 - c[1]]);
    }
    for c in corners {
        push(&[1.0 - c[0], c[1]]);
    }
    let text = format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{{"nodes": [{}]}}], "nodes": [{}],
        "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0, 0, 0, 1]}}, "emissiveFactor": [{}, {}, {}],
            "emissiveTexture": {{"index": 0, "texCoord": 0, "extensions": {{"KHR_texture_transform": {{"texCoord": 1, "offset": [0.5, 0]}}}}}},
            "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": {strength}}}}}}}],
        "samplers": [{{"magFilter": 9728}}], "textures": [{{"source": 0, "sampler": 0}}], "images": [{{"uri": "glow.png"}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3}}, "material": 0}}]}}],
        "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 72}}, {{"buffer": 0, "byteOffset": 72, "byteLength": 72}},
                        {{"buffer": 0, "byteOffset": 144, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 192, "byteLength": 48}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": 5126, "count": 6, "type": "VEC3"}},
                      {{"bufferView": 2, "componentType": 5126, "count": 6, "type": "VEC2"}},
                      {{"bufferView": 3, "componentType": 5126, "count": 6, "type": "VEC2"}}]}}"#,
        (0..nodes.len())
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        nodes.join(", "),
        factor[0],
        factor[1],
        factor[2],
        bytes.len(),
        base64::encode(&bytes)
    );
    let file = dir.join("panel.gltf");
    std::fs::write(&file, text).unwrap();
    file
}

/// The glTF light's pattern where its uvs put it. With TEXCOORD_1 = (1 − x, y) and the offset,
/// texture u = 1.5 − x (repeating: column 0 for x < ½) and v = y (row 0 for y < ½); reading
/// TEXCOORD_0 instead, or ignoring the offset, puts other texels there.
#[test]
fn gltf_emissive_texture_renders_its_pattern() {
    let dir = workdir("gltf");
    let texels = [[255, 40, 0], [0, 200, 90], [30, 30, 255], [0, 0, 0]];
    let (factor, strength) = ([1.0f32, 0.5, 0.8], 3.0f32);
    let file = emissive_quad(
        &dir,
        &texels,
        factor,
        strength,
        &[r#"{"mesh": 0, "name": "panel"}"#],
    );
    let job = prism::load::load(&file, |cfg| {
        cfg.film.width = 40;
        cfg.film.height = 30;
        // Samples within each pixel's square (the default Gaussian reaches into neighbours).
        cfg.film.filter = prism::filter::FilterConfig::Box { radius: 0.5 };
        cfg.sampler.spp = prism::config::Spp::Fixed(16);
        cfg.spectral.wavelengths = 8;
        cfg.integrator.max_depth = 1;
        cfg.outputs.bands = Some(0);
    })
    .unwrap();
    assert!(
        !job.warnings.iter().any(|w| w.contains("emissiveTexture")),
        "{:?}",
        job.warnings
    );
    assert_eq!(
        job.scene.emitters.len(),
        1,
        "one area light, no default light"
    );
    let texel_of = |p: Vec3| {
        let inside = (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y) && p.z.abs() < 1e-4;
        inside.then(|| {
            let u = 1.5 - p.x;
            let u = u - u.floor();
            (p.y * 2.0) as usize * 2 + (u * 2.0) as usize
        })
    };
    let rgb: Vec<[f64; 3]> = texels
        .iter()
        .map(|t| {
            [0, 1, 2].map(|k| srgb_decode(t[k] as f64 / 255.0) * (factor[k] * strength) as f64)
        })
        .collect();
    let n = check_texels(&job, texel_of, &rgb);
    assert!(n > 120, "only {n} pixels inside single texels");
}

/// A receiving point at `p` facing +z.
fn receiver(p: Vec3) -> SurfaceInteraction {
    receiver_facing(p, Vec3::Z)
}

fn receiver_facing(p: Vec3, n: Vec3) -> SurfaceInteraction {
    SurfaceInteraction {
        p,
        p_error: Vec3::ZERO,
        ng: n,
        frame: Frame::from_normal(n),
        uv: Vec2::ZERO,
        t: 0.0,
        shape: u32::MAX,
        prim: 0,
        time: 0.0,
        bary: glam::Vec2::ZERO,
    }
}

/// Irradiance below a textured light: a 1 × 1 square at z = 1 facing down (a Rectangle scaled
/// by ½), 4 × 4 grey texels g (some black), nearest. A grey RGB uplifts to g × D65 (the sigmoid
/// of (½, ½, ½) is the constant ½, times scale 2g), so at wavelength λ the reference is
/// E = D65(λ) Σ g_t ∫_t cos θ_x cos θ_y / r² dA (`irradiance`, its quadrature error far below
/// the tolerance). Each estimator (200,000 samples) must
/// lie within 4 of its standard errors (from the samples' spread) + 0.3% (the grey sigmoid's
/// fit to ½) of E.
#[test]
fn emitter_and_direction_sampling_agree_with_integrated_irradiance() {
    let dir = workdir("irradiance");
    write_greys(&dir);
    let greys = GREYS;
    let text = format!("(integrator: (max_depth: 2), outputs: (bands: 0), shapes: [{LIGHT}])");
    let file = dir.join("scene.ron");
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, |_| {}).unwrap();
    let scene = &job.scene;
    let em = &scene.emitters[0];
    let Emitter::Area(light) = em else { panic!() };
    let d65 = prism::spectrum::data::named_illuminant("D65").unwrap();
    for (k, &x) in [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.7, 0.2, 0.0),
        Vec3::new(-0.3, -0.8, 0.3),
    ]
    .iter()
    .enumerate()
    {
        let lambda = 450.0 + 90.0 * k as f32;
        let wl = Wavelengths::<1> {
            lambda: [lambda],
            pdf: [1.0],
        };
        let e_ref = irradiance(&greys, x) * d65.eval_one(lambda) as f64;

        let si = receiver(x);
        let n = 200_000;
        let mut rng = Pcg32::new(7 + k as u64, 1);
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        let mut checked_pdf = 0;
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some(s) = em.sample_li(&si, u, &wl, &scene.shapes) else {
                continue;
            };
            let f = (s.radiance[0] * s.wi.z.max(0.0) / s.pdf) as f64;
            s1 += f;
            s2 += f * f;
            if checked_pdf < 2000 {
                let hit = scene.intersect(&si.spawn(s.wi)).expect("towards the light");
                let pdf = em.pdf_li_hit(si.p, &hit, &scene.shapes);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
                    "pdf_li {pdf} vs sampled {}",
                    s.pdf
                );
                checked_pdf += 1;
            }
        }
        let (mean, se) = mean_se(s1, s2, n);
        eprintln!("point {x}: emitter sampling {mean:.6} ± {se:.6}, reference {e_ref:.6}");
        assert!(
            (mean - e_ref).abs() <= 4.0 * se + 3e-3 * e_ref,
            "emitter sampling at {x}: {mean} ± {se} vs {e_ref}"
        );

        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let d = prism::math::sampling::square_to_cosine_hemisphere(u);
            let Some(hit) = scene.intersect(&si.spawn(d)) else {
                continue;
            };
            if hit.ng.dot(-d) <= 0.0 {
                continue;
            }
            // cos θ / pdf = π for cosine-weighted directions.
            let f = std::f64::consts::PI * light.radiance.eval(hit.uv, &wl)[0] as f64;
            s1 += f;
            s2 += f * f;
        }
        let (mean, se) = mean_se(s1, s2, n);
        eprintln!("point {x}: direction sampling {mean:.6} ± {se:.6}");
        assert!(
            (mean - e_ref).abs() <= 4.0 * se + 3e-3 * e_ref,
            "direction sampling at {x}: {mean} ± {se} vs {e_ref}"
        );
    }
}

/// The light of `LIGHT` (1 × 1 at z = 1 facing down, 4 × 4 grey texels `greys`):
/// Σ g_t ∫_t cos θ_x cos θ_y / r² dA at `x` (facing +z), by the midpoint rule on 64 × 64 points
/// per texel, in f64. World (X, Y) on the light = (u − ½, v − ½) (Rectangle uv, scaled by ½).
fn irradiance(greys: &[f32; 16], x: Vec3) -> f64 {
    let m = 64usize;
    let mut e = 0.0f64;
    for ty in 0..4 {
        for tx in 0..4 {
            let g = greys[ty * 4 + tx] as f64;
            if g == 0.0 {
                continue;
            }
            let mut s = 0.0;
            for j in 0..m {
                for i in 0..m {
                    let u = (tx as f64 + (i as f64 + 0.5) / m as f64) / 4.0;
                    let v = (ty as f64 + (j as f64 + 0.5) / m as f64) / 4.0;
                    let d = [u - 0.5 - x.x as f64, v - 0.5 - x.y as f64, 1.0 - x.z as f64];
                    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    // cos θ_x = d_z / r (receiver +z), cos θ_y = d_z / r (light faces −z).
                    s += d[2] * d[2] / (r2 * r2);
                }
            }
            e += g * s / (16.0 * (m * m) as f64);
        }
    }
    e
}

const GREYS: [f32; 16] = [
    0.0, 0.8, 0.1, 0.0, 1.5, 0.0, 0.0, 0.3, 0.6, 0.05, 2.0, 0.0, 0.0, 0.0, 0.9, 0.4,
];

/// The textured light of the irradiance tests (`g.exr`, written by `write_greys`).
const LIGHT: &str = r#"(shape: Rectangle, flip_normals: true, to_world: [Scale((0.5, 0.5, 1)), Translate((0, 0, 1))],
                  emitter: (radiance: Bitmap(path: "g.exr", filter: Nearest, wrap: Clamp)))"#;

fn write_greys(dir: &Path) {
    exr::prelude::write_rgb_file(dir.join("g.exr"), 4, 4, |x, y| {
        let g = GREYS[y * 4 + x];
        (g, g, g)
    })
    .unwrap();
}

/// The path tracer (emitter sampling, BSDF sampling, MIS; max_depth 2: direct light only) on a
/// diffuse floor (reflectance 0.5) lit by the textured light, seen from above past the light:
/// each floor pixel's Y must be 0.5/π × the integrated irradiance at the point its centre sees
/// (grey texels: Y of g × D65 at unit luminance is g). Tolerance: 5 of the pixel's standard
/// errors + 2% (the irradiance varies over a pixel's footprint; the centre stands for it to
/// second order) + 1e-5.
#[test]
fn path_tracer_lights_a_floor_as_integrated() {
    let dir = workdir("floor");
    write_greys(&dir);
    let text = format!(
        r#"(
        camera: (fov: 50, to_world: [LookAt(origin: (0.3, -0.2, 3), target: (0.3, -0.2, 0), up: (0, 1, 0))]),
        film: (width: 48, height: 48, filter: Box()),
        sampler: (kind: Independent, spp: 64),
        spectral: (wavelengths: 4),
        integrator: (max_depth: 2),
        outputs: (bands: 0),
        materials: {{"floor": Diffuse(reflectance: Constant(0.5))}},
        shapes: [(shape: Rectangle, material: "floor", to_world: [Scale((3, 3, 1))]), {LIGHT}],
    )"#
    );
    let file = dir.join("scene.ron");
    std::fs::write(&file, text).unwrap();
    let job = prism::load::load(&file, |_| {}).unwrap();
    let (means, errs) = render_xyz(&job);
    let hits = pixel_hits(&job);
    let (mut checked, mut worst) = (0, 0.0f64);
    for (i, h) in hits.iter().enumerate() {
        // Floor pixels only (the light's back, at z = 1, hides what is under it).
        let Some(h) = h else { continue };
        if h.iter().any(|p| p.z.abs() > 1e-4) {
            continue;
        }
        let want = 0.5 / std::f64::consts::PI * irradiance(&GREYS, h[0]);
        let (got, se) = (means[i][1], errs[i][1]);
        worst = worst.max((got - want).abs() / want.max(1e-9));
        assert!(
            (got - want).abs() <= 5.0 * se + 0.02 * want + 1e-5,
            "pixel {i} at {}: Y {got} ± {se} vs {want}",
            h[0]
        );
        checked += 1;
    }
    eprintln!("{checked} floor pixels; largest relative deviation {worst:.4}");
    assert!(checked > 1000, "only {checked} floor pixels");
}

fn mean_se(s1: f64, s2: f64, n: usize) -> (f64, f64) {
    let n = n as f64;
    let mean = s1 / n;
    let var = (s2 / n - mean * mean).max(0.0) * n / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A 4 × 4 grid of quads over [0, 1]² (z = 0, +z, uv = (x, y)), each split along its
/// (0,0)–(1,1) diagonal: 32 triangles, triangle 2q below the diagonal, 2q + 1 above.
fn grid_mesh() -> Mesh {
    let mut m = Mesh::default();
    for j in 0..=4 {
        for i in 0..=4 {
            let (x, y) = (i as f32 / 4.0, j as f32 / 4.0);
            m.positions.push(Vec3::new(x, y, 0.0));
            m.normals.push(Vec3::Z);
            m.uvs.push(Vec2::new(x, y));
        }
    }
    for j in 0..4u32 {
        for i in 0..4u32 {
            let v = |a: u32, b: u32| (j + b) * 5 + i + a;
            m.indices.push([v(0, 0), v(1, 0), v(1, 1)]);
            m.indices.push([v(0, 0), v(1, 1), v(0, 1)]);
        }
    }
    m
}

/// The triangle of `grid_mesh` holding (x, y), and which quarter of it (midpoint subdivision:
/// 0–2 the corner sub-triangles at vertices 0–2, 3 the middle one).
fn locate(m: &Mesh, p: Vec3) -> (usize, usize) {
    let (i, j) = (((p.x * 4.0) as usize).min(3), ((p.y * 4.0) as usize).min(3));
    let (fx, fy) = (p.x * 4.0 - i as f32, p.y * 4.0 - j as f32);
    let t = 2 * (j * 4 + i) + usize::from(fy > fx);
    let [a, b, c] = m.indices[t].map(|k| m.positions[k as usize]);
    // Barycentrics of p in (a, b, c), in 2D.
    let (v0, v1, v2) = ((b - a).truncate(), (c - a).truncate(), (p - a).truncate());
    let den = v0.x * v1.y - v1.x * v0.y;
    let b1 = (v2.x * v1.y - v1.x * v2.y) / den;
    let b2 = (v0.x * v2.y - v2.x * v0.y) / den;
    let b0 = 1.0 - b1 - b2;
    let q = if b0 > 0.5 {
        0
    } else if b1 > 0.5 {
        1
    } else if b2 > 0.5 {
        2
    } else {
        3
    };
    (t, q)
}

/// The weighted triangle sampler: points from `sample_area_uv` binned by triangle and quarter,
/// against N × (the area density `pdf_li` reports for the triangle) × (a quarter of its area):
/// Pearson's χ², p > 1e-4 (seeded, so reproducible). The texture (8 × 8, nearest) is black in
/// its first two columns (x < ¼) and its last row (y ≥ ⅞): the quads of the first column emit
/// nothing, get weight 0, no sample and zero density. The reported `pdf_area` of every sample
/// equals its triangle's `pdf_li` density (the same number, f32 rounding).
#[test]
fn weighted_triangle_sampler_matches_its_pdf() {
    let mesh = grid_mesh();
    let mut pixels = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let g = 0.2 + 0.1 * ((x * 3 + y * 5) % 7) as f32;
            let on = x >= 2 && y < 7;
            pixels.push(if on { [g, 0.5 * g, 0.3 + g] } else { [0.0; 3] });
        }
    }
    let img = RgbImage {
        width: 8,
        height: 8,
        pixels,
        source: None,
    };
    let tex = EmissionTexture::new(
        prism::spectrum::gamut::Gamut::Srgb,
        &img,
        [1.0; 3],
        [Wrap::Clamp; 2],
        TexFilter::Nearest,
        UvMap::IDENTITY,
    );
    let shape = Shape::Mesh(mesh.clone());
    let light = AreaEmitter::with_radiance(0, &shape, AreaRadiance::Textured(Box::new(tex)));
    let shapes = vec![shape.clone()];
    // Area density of triangle t: pdf_li from 1 above its centroid (cos = 1, r² = 1).
    let density = |t: usize| -> f64 {
        let [a, b, c] = mesh.indices[t].map(|k| mesh.positions[k as usize]);
        let centroid = (a + b + c) / 3.0;
        let mut hit = receiver(centroid);
        hit.prim = t as u32;
        hit.shape = 0;
        light.pdf_li(centroid + Vec3::Z, &hit, &shapes) as f64
    };
    let n = 400_000usize;
    let mut counts = vec![0.0f64; 32 * 4];
    let mut rng = Pcg32::new(11, 3);
    for _ in 0..n {
        let (s, uv) = light.sample_area_uv(Vec2::new(rng.next_f32(), rng.next_f32()), &shape);
        let (t, q) = locate(&mesh, s.p);
        assert!((uv - s.p.truncate()).length() < 1e-5, "uv {uv} at {}", s.p);
        let d = density(t);
        assert!(
            ((s.pdf_area as f64) - d).abs() <= 1e-5 * d,
            "triangle {t}: sampled pdf {} vs pdf_li {d}",
            s.pdf_area
        );
        counts[t * 4 + q] += 1.0;
    }
    let tri_area = 0.5 / 16.0;
    let mut expected = Vec::new();
    for t in 0..32 {
        let d = density(t);
        let black_column = t % 8 < 2;
        if black_column {
            assert_eq!(d, 0.0, "triangle {t} emits nothing but has density {d}");
            assert!(
                (0..4).all(|q| counts[t * 4 + q] == 0.0),
                "triangle {t} sampled"
            );
        } else {
            assert!(d > 0.0, "triangle {t} emits but has zero density");
        }
        for _ in 0..4 {
            expected.push(n as f64 * d * tri_area / 4.0);
        }
    }
    let total: f64 = expected.iter().sum();
    assert!(
        (total - n as f64).abs() < 1e-3 * n as f64,
        "densities integrate to {}",
        total / n as f64
    );
    let (p, stat, dof) = prism::math::chi2::chi2_test(&counts, &expected);
    eprintln!("weighted triangles: chi2 {stat:.1}, dof {dof}, p = {p:.3e}");
    assert!(p > 1e-4, "chi2 {stat} with {dof} dof, p = {p:e}");
}

/// An emissive glTF mesh under two nodes is instanced (no longer copied into world space), and
/// its lights sample the instances as the flattened copies do: the same random numbers give
/// the same irradiance estimate at a point facing both (relative 1e-4: the instances' points
/// round differently in the last bits), and `pdf_li` at each instance hit equals the sampled
/// density (1e-3, f32 rounding).
#[test]
fn emissive_gltf_instances_light_like_copies() {
    let dir = workdir("instances");
    let texels = [[255, 40, 0], [0, 200, 90], [30, 30, 255], [0, 0, 0]];
    let file = emissive_quad(
        &dir,
        &texels,
        [1.0, 1.0, 1.0],
        2.0,
        &[
            r#"{"mesh": 0, "name": "left", "translation": [-0.7, 0, 0]}"#,
            r#"{"mesh": 0, "name": "right", "translation": [0.8, 0.1, 0], "scale": [1.5, 1, 1]}"#,
        ],
    );
    let load = |flatten: bool| {
        prism::load::load(&file, |cfg| {
            cfg.flatten = flatten;
            cfg.outputs.bands = Some(0);
        })
        .unwrap()
    };
    let (inst, flat) = (load(false), load(true));
    assert!(inst
        .scene
        .shapes
        .iter()
        .all(|s| matches!(s, Shape::Instance(_))));
    assert!(flat
        .scene
        .shapes
        .iter()
        .all(|s| matches!(s, Shape::Mesh(_))));
    assert_eq!(
        (inst.scene.emitters.len(), flat.scene.emitters.len()),
        (2, 2)
    );
    let wl = Wavelengths::<4> {
        lambda: [430.0, 510.0, 590.0, 670.0],
        pdf: [1.0; 4],
    };
    let si = receiver_facing(Vec3::new(0.3, 0.4, 1.5), -Vec3::Z);
    let estimate = |job: &prism::load::Job| -> [f64; 4] {
        let scene = &job.scene;
        let mut sum = [0.0f64; 4];
        let mut rng = Pcg32::new(5, 9);
        for _ in 0..20_000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            for em in &scene.emitters {
                let Some(s) = em.sample_li(&si, u, &wl, &scene.shapes) else {
                    continue;
                };
                let cos = si.ng.dot(s.wi).max(0.0);
                for (k, acc) in sum.iter_mut().enumerate() {
                    *acc += (s.radiance[k] * cos / s.pdf) as f64;
                }
                let hit = scene.intersect(&si.spawn(s.wi)).expect("towards a light");
                let e = scene.shape_emitter[hit.shape as usize].expect("a light");
                let pdf = scene.emitters[e as usize].pdf_li_hit(si.p, &hit, &scene.shapes);
                if std::ptr::eq(&scene.emitters[e as usize], em) {
                    assert!(
                        (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
                        "pdf_li {pdf} vs {}",
                        s.pdf
                    );
                }
            }
        }
        sum
    };
    let (a, b) = (estimate(&inst), estimate(&flat));
    eprintln!("instanced {a:?}, flattened {b:?}");
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!(
            *x > 0.0 && (x - y).abs() <= 1e-4 * y,
            "lane {k}: {x} vs {y}"
        );
    }
}
