//! The spot, directional and envmap emitters against Mitsuba 3.9.1's own: values in
//! `tests/data/emitters_mitsuba.json`, made by `tools/reference/emitters_reference.py`, which
//! queries Mitsuba's emitter plugins (scalar_spectral) directly, so the values are exact (no
//! Monte Carlo noise).
//!
//! - envmap orientation: for a grey map, eval(map, d) / eval(white map, d) is the bilinear
//!   interpolation of the texel values at d, independent of the RGB-to-spectrum table; it pins
//!   down which direction maps to which pixel, with and without a `to_world` rotation. Tolerance
//!   1e-4 relative: both sides compute in f32, and a wrong orientation or texel offset moves
//!   values by tens of percent.
//! - envmap uplift: the absolute radiance of uniform maps of several colours with `scale` 2, at
//!   360–830 nm. prism and Mitsuba fit the Jakob–Hanika sigmoid tables independently (prism's in
//!   its build script), and normalise D65 from different CIE tables (≈0.1%), so this is a
//!   tolerance on the uplift itself: 1% of the value plus 0.2% of the spectrum's maximum (the
//!   measured worst case is a few times smaller; a wrong scale convention, e.g. max(rgb) instead
//!   of 2·max(rgb), or a missing D65 factor, is off by ≥ 50%).
//! - spot: the falloff factor L·r²/I at angles across the beam edge and the cutoff. Tolerance
//!   1e-4 absolute (f32 acos near the transition). The default intensity (D65 at unit
//!   luminance) on the axis, 0.3% relative (the D65 normalisations differ by ≈0.1%).
//! - directional: the direction towards the light, for `direction` and for a `to_world`
//!   look-at (1e-6), and the irradiance: the default (D65, 0.3% as above) and a constant (1e-6).

mod common;

use common::receiver;
use glam::{Mat3, Vec2, Vec3};
use prism::emitter::{Emitter, EnvMap};
use prism::math::portable;
use prism::spectrum::Wavelengths;
use prism::texture::RgbImage;
use serde_json::Value;
use std::path::Path;

fn reference() -> Value {
    serde_json::from_str(&std::fs::read_to_string("tests/data/emitters_mitsuba.json").unwrap())
        .unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn wl550() -> Wavelengths<1> {
    Wavelengths {
        lambda: [550.0],
        pdf: [1.0],
    }
}

/// The first emitter of a scene in `tests/data` (so relative image paths resolve there).
fn emitter(ron: &str) -> Emitter {
    let text = format!("(film: (width: 2, height: 2), emitters: [{ron}], outputs: (bands: 0))");
    let job = prism::load::load_str(&text, Path::new("tests/data/inline.ron")).unwrap();
    job.scene.emitters[0].clone()
}

#[test]
fn envmap_orientation_and_interpolation_match_mitsuba() {
    let r = reference();
    let env = &r["envmap"];
    let dirs: Vec<Vec3> = env["directions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            let v = floats(d);
            Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
        })
        .collect();
    let axis = floats(&env["rotation"]["axis"]);
    let angle = env["rotation"]["angle"].as_f64().unwrap();
    let file = env["file"].as_str().unwrap();
    let white = RgbImage {
        width: 16,
        height: 8,
        pixels: vec![[1.0; 3]; 16 * 8],
        source: None,
    };
    let rot = Mat3::from_mat4(prism::math::rotation::axis_angle(
        Vec3::new(axis[0] as f32, axis[1] as f32, axis[2] as f32).normalize(),
        (angle as f32).to_radians(),
    ));
    for (key, to_world, m) in [
        ("identity", String::new(), Mat3::IDENTITY),
        (
            "rotated",
            format!(
                "to_world: [Rotate(axis: ({}, {}, {}), angle: {angle})]",
                axis[0], axis[1], axis[2]
            ),
            rot,
        ),
    ] {
        let map = emitter(&format!("Envmap(filename: \"{file}\", {to_world})"));
        let white = EnvMap::new(&white, 1.0, m);
        let expect = floats(&env[key]);
        assert_eq!(expect.len(), dirs.len());
        let mut worst = 0.0f64;
        for (d, e) in dirs.iter().zip(expect) {
            let got = map.le_env(*d, &wl550())[0] / white.eval(*d, &wl550())[0];
            assert!(
                (got as f64 - e).abs() <= 1e-4 * e.abs() + 1e-6,
                "{key}: direction {d}: prism {got}, Mitsuba {e}"
            );
            worst = worst.max((got as f64 / e - 1.0).abs());
        }
        eprintln!(
            "envmap {key}: {} directions, worst relative difference {worst:.2e}",
            dirs.len()
        );
    }
}

#[test]
fn spot_falloff_matches_mitsuba() {
    let r = reference();
    let spot = &r["spot"];
    let angles = floats(&spot["angles"]);
    for (key, params) in [
        ("default", ""),
        ("custom", "cutoff_angle: 30, beam_width: 20,"),
    ] {
        let em = emitter(&format!(
            "Spot(intensity: Constant(3), {params} to_world: [LookAt(origin: (0, 2, 0), target: (0, 0, 0), up: (0, 0, 1))])"
        ));
        let expect = floats(&spot[key]["falloff"]);
        let mut worst = 0.0f64;
        for (deg, e) in angles.iter().zip(expect) {
            let x = 2.0 * portable::tan(deg.to_radians()) as f32;
            let si = receiver(Vec3::new(x, 0.0, 0.0));
            let got = em
                .sample_li(&si, Vec2::splat(0.5), &wl550(), &[])
                .map_or(0.0, |s| s.radiance[0] * (4.0 + x * x) / 3.0);
            assert!(
                (got as f64 - e).abs() <= 1e-4,
                "{key} at {deg}°: prism {got}, Mitsuba {e}"
            );
            worst = worst.max((got as f64 - e).abs());
        }
        eprintln!(
            "spot {key}: {} angles, worst difference {worst:.2e}",
            angles.len()
        );
    }
}

/// The reference's wavelengths.
fn wavelengths(r: &Value) -> Vec<f32> {
    floats(&r["wavelengths"])
        .iter()
        .map(|&w| w as f32)
        .collect()
}

fn at(lambda: f32) -> Wavelengths<1> {
    Wavelengths {
        lambda: [lambda],
        pdf: [1.0],
    }
}

/// Checks `got` against Mitsuba's `expect` at each wavelength, |Δ| ≤ rel·|e| + abs; returns the
/// worst relative difference.
fn compare(name: &str, wls: &[f32], got: &[f32], expect: &[f64], rel: f64, abs: f64) -> f64 {
    assert_eq!(got.len(), expect.len());
    let mut worst = 0.0f64;
    for ((l, &g), &e) in wls.iter().zip(got).zip(expect) {
        let d = (g as f64 - e).abs();
        assert!(
            d <= rel * e.abs() + abs,
            "{name} at {l} nm: prism {g}, Mitsuba {e}"
        );
        worst = worst.max(d / e.abs().max(1e-12));
    }
    eprintln!("{name}: worst relative difference {worst:.2e}");
    worst
}

#[test]
fn envmap_uplift_and_scale_match_mitsuba() {
    let r = reference();
    let wls = wavelengths(&r);
    let up = &r["envmap"]["uplift"];
    let scale = up["scale"].as_f64().unwrap();
    let d = floats(&up["direction"]);
    let d = Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32).normalize();
    let dir = std::env::temp_dir().join(format!("prism-uplift-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (colour, values) in up["colours"]
        .as_array()
        .unwrap()
        .iter()
        .zip(up["values"].as_array().unwrap())
    {
        let c = floats(colour);
        let (r, g, b) = (c[0] as f32, c[1] as f32, c[2] as f32);
        // A uniform 8×4 map, loaded through the scene description with `scale`.
        let file = dir.join("uniform.exr");
        exr::prelude::write_rgb_file(&file, 8, 4, |_, _| (r, g, b)).unwrap();
        let text = format!(
            "(film: (width: 2, height: 2), emitters: [Envmap(filename: \"uniform.exr\", scale: {scale})], outputs: (bands: 0))"
        );
        let job = prism::load::load_str(&text, &dir.join("inline.ron")).unwrap();
        let em = &job.scene.emitters[0];
        let got: Vec<f32> = wls.iter().map(|&l| em.le_env(d, &at(l))[0]).collect();
        let expect = floats(values);
        let peak = expect.iter().cloned().fold(0.0, f64::max);
        compare(
            &format!("envmap uplift of {c:?}"),
            &wls,
            &got,
            &expect,
            1e-2,
            2e-3 * peak,
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn spot_default_intensity_matches_mitsuba() {
    let r = reference();
    let wls = wavelengths(&r);
    let em =
        emitter("Spot(to_world: [LookAt(origin: (0, 2, 0), target: (0, 0, 0), up: (0, 0, 1))])");
    let si = receiver(Vec3::ZERO);
    let got: Vec<f32> = wls
        .iter()
        .map(|&l| {
            em.sample_li(&si, Vec2::splat(0.5), &at(l), &[])
                .unwrap()
                .radiance[0]
                * 4.0
        })
        .collect();
    compare(
        "spot default intensity",
        &wls,
        &got,
        &floats(&r["spot"]["default_intensity"]),
        3e-3,
        0.0,
    );
}

#[test]
fn directional_matches_mitsuba() {
    let r = reference();
    let wls = wavelengths(&r);
    let cases = &r["directional"];
    let d = floats(&cases["direction"]["direction"]);
    let t = floats(&cases["to_world"]["look_at_target"]);
    let e = cases["to_world"]["irradiance_value"].as_f64().unwrap();
    for (key, ron, rel) in [
        (
            "direction",
            format!("Directional(direction: ({}, {}, {}))", d[0], d[1], d[2]),
            3e-3,
        ),
        (
            "to_world",
            format!(
                "Directional(irradiance: Constant({e}), to_world: [LookAt(origin: (0, 0, 0), target: ({}, {}, {}), up: (0, 1, 0))])",
                t[0], t[1], t[2]
            ),
            1e-6,
        ),
    ] {
        let em = emitter(&ron);
        let si = receiver(Vec3::new(0.3, 0.1, -0.2));
        let s = em.sample_li(&si, Vec2::splat(0.5), &at(550.0), &[]).unwrap();
        assert!(s.delta && s.pdf == 1.0);
        let to_light = floats(&cases[key]["to_light"]);
        let expect = Vec3::new(to_light[0] as f32, to_light[1] as f32, to_light[2] as f32);
        assert!(
            s.wi.abs_diff_eq(expect, 1e-6),
            "{key}: towards the light: prism {}, Mitsuba {expect}",
            s.wi
        );
        let got: Vec<f32> = wls
            .iter()
            .map(|&l| em.sample_li(&si, Vec2::splat(0.5), &at(l), &[]).unwrap().radiance[0])
            .collect();
        compare(
            &format!("directional {key} irradiance"),
            &wls,
            &got,
            &floats(&cases[key]["irradiance"]),
            rel,
            0.0,
        );
    }
}
