//! Every material, tested through its public interface (`Material::bsdf` → `Bsdf<N>`):
//!
//! - **chi-square**: directions drawn by `sample` match `pdf`, at several incident angles (and
//!   roughnesses, where the material has one). Smooth directions are binned over the whole
//!   sphere in (1 − cos θ, φ) cells; Dirac samples form one extra cell whose expected count is
//!   n·(1 − ∫pdf). Passes if p > α = 1% / (number of chi-square tests in this file) (Šidák).
//! - **consistency**: each smooth sample's weight equals eval/pdf (relative 1e-3, f32 rounding).
//! - **reciprocity**: f(wi, wo) = f(wo, wi) for reflection (relative 1e-3).
//! - **energy (white furnace)**: the albedo E[weight] ≤ 1 everywhere; = 1 for lossless cases.
//!   Tolerance: 4 standard errors of the 100k-sample mean.

mod common;

use common::{alpha, chi2_test};
use glam::{Vec2, Vec3};
use prism::bsdf::{Bsdf, Material};
use prism::interaction::SurfaceInteraction;
use prism::math::rng::Pcg32;
use prism::math::Frame;
use prism::spectrum::{WavelengthSampler, WavelengthSampling, Wavelengths};
use std::f64::consts::PI;
use std::path::Path;

/// Chi-square tests this file runs (for the significance level).
const CHI2_TESTS: usize = 60;

/// A material from its RON config (through the scene loader, so checks apply).
pub fn material(cfg: &str) -> Material {
    let text = format!(
        "(film: (width: 2, height: 2), outputs: (bands: 0), materials: {{ \"m\": {cfg} }}, shapes: [(shape: Rectangle, material: \"m\")])"
    );
    let job = prism::scene::load_str(&text, Path::new("inline.ron"))
        .unwrap_or_else(|e| panic!("{cfg}: {e}"));
    job.scene.materials[0].clone()
}

fn hit() -> SurfaceInteraction {
    SurfaceInteraction {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::from_normal(Vec3::Z),
        uv: Vec2::new(0.3, 0.7),
        t: 1.0,
        shape: 0,
        prim: 0,
    }
}

fn wavelengths(u: f32) -> Wavelengths<4> {
    WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0).sample(u)
}

fn bsdf(m: &Material, wi: Vec3) -> Bsdf<'_, 4> {
    m.bsdf(&hit(), wi, &wavelengths(0.37))
}

/// An incident direction at `theta_deg` from the normal (negative: from below).
pub fn dir(theta_deg: f32) -> Vec3 {
    let t = theta_deg.abs().to_radians();
    let z = if theta_deg < 0.0 { -t.cos() } else { t.cos() };
    Vec3::new(t.sin() * 0.8, t.sin() * 0.6, z).normalize()
}

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

/// Chi-square test of `sample` against `pdf` for incident direction `wi`.
pub fn chi2(name: &str, m: &Material, wi: Vec3) {
    const NT: usize = 40;
    const NP: usize = 80;
    const SUB: usize = 10;
    let n = 200_000usize;
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(0xb5df, 3);
    let mut observed = vec![0.0; NT * NP + 1];
    let dcos = 2.0 / NT as f64;
    let dphi = 2.0 * PI / NP as f64;
    for _ in 0..n {
        let Some(s) = b.sample(wi, rng.next_f32(), u2(&mut rng)) else {
            continue;
        };
        if s.delta {
            observed[NT * NP] += 1.0;
            continue;
        }
        let w = s.wo.as_dvec3().normalize();
        let it = (((1.0 - w.z) / dcos) as usize).min(NT - 1);
        let ip = ((w.y.atan2(w.x).rem_euclid(2.0 * PI) / dphi) as usize).min(NP - 1);
        observed[it * NP + ip] += 1.0;
    }
    let mut expected = vec![0.0; NT * NP + 1];
    let mut total = 0.0;
    for it in 0..NT {
        for ip in 0..NP {
            let mut sum = 0.0;
            for a in 0..SUB {
                for c in 0..SUB {
                    let z = 1.0 - (it as f64 + (a as f64 + 0.5) / SUB as f64) * dcos;
                    let phi = (ip as f64 + (c as f64 + 0.5) / SUB as f64) * dphi;
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    let wo = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
                    sum += b.pdf(wi, wo) as f64;
                }
            }
            let e = sum / (SUB * SUB) as f64 * dcos * dphi * n as f64;
            expected[it * NP + ip] = e;
            total += e;
        }
    }
    // Samples the material refuses (None) are not drawn at all: scale to the accepted ones.
    let accepted: f64 = observed.iter().sum();
    let delta_expected = (accepted - total).max(0.0);
    expected[NT * NP] = delta_expected;
    let (p, stat, dof) = chi2_test(&observed, &expected);
    let a = alpha(CHI2_TESTS);
    assert!(p > a, "{name} wi={wi:?}: chi-square {stat:.1} ({dof} dof), p = {p:.2e} < {a:.1e}; delta samples {} vs expected {delta_expected:.0}", observed[NT * NP]);
}

/// Each smooth sample's weight is eval / pdf, lane by lane.
pub fn consistency(name: &str, m: &Material, wi: Vec3) {
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(7, 7);
    for _ in 0..2000 {
        let Some(s) = b.sample(wi, rng.next_f32(), u2(&mut rng)) else {
            continue;
        };
        if s.delta {
            continue;
        }
        let (f, pdf) = (b.eval(wi, s.wo), b.pdf(wi, s.wo));
        assert!(
            (pdf - s.pdf).abs() <= 1e-3 * pdf,
            "{name}: sample pdf {} vs pdf() {pdf}",
            s.pdf
        );
        for k in 0..4 {
            let expect = f[k] / pdf;
            assert!(
                (s.weight[k] - expect).abs() <= 1e-3 * expect.abs().max(1e-3),
                "{name} lane {k}: weight {} vs eval/pdf {expect}",
                s.weight[k]
            );
        }
    }
}

/// f(wi, wo) = f(wo, wi) for reflected directions (eval includes |cos θ_o|, divided out here).
pub fn reciprocity(name: &str, m: &Material) {
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..500 {
        let a = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
        let c = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
        if a.z < 0.05 || c.z < 0.05 {
            continue;
        }
        let f1 = bsdf(m, a).eval(a, c)[0] / c.z;
        let f2 = bsdf(m, c).eval(c, a)[0] / a.z;
        assert!(
            (f1 - f2).abs() <= 1e-3 * f1.abs().max(f2.abs()).max(1e-6),
            "{name}: f({a:?}, {c:?}) = {f1} but f reversed = {f2}"
        );
    }
}

/// Albedo E[weight] of the hero lane from `wi`, with its standard error.
pub fn albedo(m: &Material, wi: Vec3) -> (f64, f64) {
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(9, 9);
    let n = 100_000;
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let w = b
            .sample(wi, rng.next_f32(), u2(&mut rng))
            .map_or(0.0, |s| s.weight[0] as f64);
        s1 += w;
        s2 += w * w;
    }
    let mean = s1 / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

pub fn energy_at_most_one(name: &str, m: &Material) {
    for t in [0.0, 30.0, 60.0, 80.0, 89.0] {
        let (a, se) = albedo(m, dir(t));
        assert!(
            a <= 1.0 + 4.0 * se + 1e-6,
            "{name} θ={t}: albedo {a} ± {se} exceeds 1"
        );
    }
}

pub fn energy_is_one(name: &str, m: &Material, angles: &[f32]) {
    for &t in angles {
        let (a, se) = albedo(m, dir(t));
        assert!(
            (a - 1.0).abs() <= 4.0 * se + 1e-4,
            "{name} θ={t}: albedo {a} ± {se}, expected 1"
        );
    }
}

#[test]
fn diffuse() {
    let m = material("Diffuse(reflectance: Constant(0.8))");
    for t in [0.0, 45.0, 85.0] {
        chi2("diffuse", &m, dir(t));
        consistency("diffuse", &m, dir(t));
    }
    reciprocity("diffuse", &m);
    energy_at_most_one("diffuse", &m);
    // Albedo of a Lambertian surface is its reflectance.
    let (a, se) = albedo(&m, dir(40.0));
    assert!((a - 0.8).abs() <= 4.0 * se + 1e-6, "{a}");
    assert!(
        bsdf(&m, dir(-40.0))
            .sample(dir(-40.0), 0.5, Vec2::splat(0.5))
            .is_none(),
        "one-sided"
    );
}

#[test]
fn twosided_mirrors_the_back() {
    let m = material("Twosided(bsdf: Diffuse(reflectance: Constant(0.6)))");
    for t in [30.0, -30.0, -80.0] {
        chi2("twosided", &m, dir(t));
        consistency("twosided", &m, dir(t));
    }
    let (a, se) = albedo(&m, dir(-50.0));
    assert!((a - 0.6).abs() <= 4.0 * se + 1e-6, "back side albedo {a}");
    // Different BSDFs per side.
    let m = material("Twosided(bsdf: Diffuse(reflectance: Constant(0.2)), back: Diffuse(reflectance: Constant(0.9)))");
    assert!(
        (albedo(&m, dir(20.0)).0 - 0.2).abs() < 0.01
            && (albedo(&m, dir(-20.0)).0 - 0.9).abs() < 0.01
    );
}

#[test]
fn blend_and_mask() {
    let blend = material("Blend(weight: 0.25, bsdf0: Diffuse(reflectance: Constant(0.8)), bsdf1: Mask(opacity: 0.5, bsdf: Diffuse(reflectance: Constant(0.4))))");
    for t in [10.0, 70.0] {
        chi2("blend+mask", &blend, dir(t));
        consistency("blend+mask", &blend, dir(t));
    }
    // 0.75·0.8 + 0.25·(0.5·0.4 + 0.5·1 (pass-through)) = 0.6 + 0.175.
    let (a, se) = albedo(&blend, dir(30.0));
    assert!((a - 0.775).abs() <= 4.0 * se + 1e-6, "blend albedo {a}");
    let mask = material("Mask(opacity: 0.0, bsdf: Diffuse())");
    energy_is_one("fully transparent mask", &mask, &[0.0, 60.0, -60.0]);
}

#[test]
fn plastic() {
    let m = material("Plastic(diffuse_reflectance: Constant(0.5))");
    for t in [0.0, 45.0, 80.0] {
        chi2("plastic", &m, dir(t));
        consistency("plastic", &m, dir(t));
    }
    reciprocity("plastic", &m);
    // Albedo = F(θi) + (1 − F(θi))·ρ exactly: internal reflections are folded in with the
    // hemispherical Fresnel averages, and 1 − F̄_int = (1 − F̄_ext)/η².
    for t in [0.0f32, 50.0, 80.0] {
        let eta = 1.49 / 1.000_277;
        let f = prism::bsdf::fresnel::dielectric(dir(t).z, eta).0 as f64;
        let (a, se) = albedo(&m, dir(t));
        let expect = f + (1.0 - f) * 0.5;
        assert!(
            (a - expect).abs() <= 4.0 * se + 1e-3,
            "θ={t}: albedo {a} ± {se}, expected {expect}"
        );
    }
    let white = material("Plastic(diffuse_reflectance: Constant(1.0))");
    energy_is_one("white plastic", &white, &[0.0, 40.0, 75.0]);
    let nonlinear = material("Plastic(diffuse_reflectance: Constant(0.9), nonlinear: true)");
    energy_at_most_one("nonlinear plastic", &nonlinear);
}

#[test]
fn rough_plastic() {
    for dist in ["Beckmann", "Ggx"] {
        for alpha in [0.1, 0.4] {
            let m = material(&format!("RoughPlastic(distribution: {dist}, alpha: {alpha}, diffuse_reflectance: Rgb(0.7, 0.3, 0.2))"));
            let name = format!("roughplastic {dist} α={alpha}");
            for t in [0.0, 60.0] {
                chi2(&name, &m, dir(t));
                consistency(&name, &m, dir(t));
            }
            reciprocity(&name, &m);
            energy_at_most_one(&name, &m);
        }
    }
    // With a white base and low roughness the model is close to lossless (the single-scattering
    // microfacet coating loses a little at grazing angles).
    let m = material("RoughPlastic(alpha: 0.05, diffuse_reflectance: Constant(1.0))");
    let (a, se) = albedo(&m, dir(0.0));
    assert!(a <= 1.0 + 4.0 * se && a > 0.97, "albedo {a}");
}
