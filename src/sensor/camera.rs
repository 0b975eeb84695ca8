//! A camera: three measured spectral sensitivities, white balance, the camera-RGB → XYZ matrix
//! and exposure.
//!
//! - Camera channel c (before white balance and exposure): C_c = ∫ L c̄ dλ / ∫ ḡ dλ, so a
//!   constant spectrum of 1 reads G = 1 (as Y does).
//! - White balance to an illuminant W: multipliers m_c = C_g(W) / C_c(W) (W reads neutral).
//! - The matrix (as pbrt-v4's PixelSensor): the 24 ColorChecker patches ρ_i are seen under W (D65
//!   when white balance is off): rgb_i = m ∘ C(ρ_i W) / C_g(W); their targets are their XYZ
//!   under D65, xyz_i = XYZ(ρ_i D65) / Y(D65); M = argmin Σ |M rgb_i − xyz_i|², by the normal
//!   equations M = (Σ xyz_i rgb_iᵀ)(Σ rgb_i rgb_iᵀ)⁻¹. Integrals are sums over 1 nm steps,
//!   360–830 nm (the curves are linear between their samples; the ColorChecker data, 380–780 nm,
//!   hold their end values outside).
//! - Exposure: a thin lens focused at infinity, on axis, lens transmittance 1, puts irradiance
//!   E = L·π / (4 N²) on the sensor; over shutter time t that is H = E·t, and the ISO speed is a
//!   gain of ISO/100: the camera layers are C · k with k = (ISO/100) · t · π / (4 N²). Without
//!   `exposure`, k = 1.

use super::colour_space::RgbSpace;
use crate::spectrum::color::Cmf;
use crate::spectrum::{data, table, Curve};
use glam::{DMat3, DVec3, Mat3, Vec3};

/// Named cameras: the 17 PhysLight cameras pbrt-v4 ships and two NPL measurements from
/// colour-science (`spectra/cameras/<name>.txt`).
pub const CAMERAS: [&str; 19] = [
    "canon_eos_100d",
    "canon_eos_1dx_mkii",
    "canon_eos_200d",
    "canon_eos_200d_mkii",
    "canon_eos_5d",
    "canon_eos_5d_mkii",
    "canon_eos_5d_mkiii",
    "canon_eos_5d_mkiv",
    "canon_eos_5ds",
    "canon_eos_m",
    "hasselblad_l1d_20c",
    "nikon_d810",
    "nikon_d850",
    "sony_ilce_6400",
    "sony_ilce_7m3",
    "sony_ilce_7rm3",
    "sony_ilce_9",
    "nikon_d5100_npl",
    "sigma_sd_merrill_npl",
];

/// The r, g, b curves of a named camera.
pub fn named(name: &str) -> Option<[Curve; 3]> {
    if !CAMERAS.contains(&name) {
        return None;
    }
    let text = data::embedded(&format!("cameras/{name}"))?;
    let t = table::parse(text).expect("embedded camera table parses");
    Some(["r", "g", "b"].map(|c| Curve::from_samples(&t.wavelengths, t.column(c).unwrap())))
}

/// The 24 ColorChecker reflectances (`spectra/colorchecker.txt`), held at their end values
/// outside the data's 380–780 nm.
pub fn colorchecker() -> Vec<Curve> {
    let t = table::parse(data::embedded("colorchecker").expect("embedded"))
        .expect("embedded ColorChecker table parses");
    t.values
        .iter()
        .map(|v| {
            let (first, last) = (t.wavelengths[0], *t.wavelengths.last().unwrap());
            let mut nm = vec![300.0];
            let mut vals = vec![v[0]];
            nm.extend(&t.wavelengths);
            vals.extend(v);
            nm.push(last.max(first) + 400.0);
            vals.push(*v.last().unwrap());
            Curve::from_samples(&nm, &vals)
        })
        .collect()
}

/// Σ over 1 nm steps from 360 to 830 nm of f(λ).
fn sum_nm(f: impl Fn(f32) -> f64) -> f64 {
    (360..=830).map(|l| f(l as f32)).sum()
}

/// C(S) before normalisation: Σ S c̄ for the three curves.
fn camera_sum(curves: &[Curve; 3], s: impl Fn(f32) -> f64) -> DVec3 {
    let v = curves
        .each_ref()
        .map(|c| sum_nm(|l| s(l) * c.eval_one(l) as f64));
    DVec3::from_array(v)
}

/// White-balance multipliers for illuminant `w`: m_c = C_g(W) / C_c(W).
pub fn white_balance(curves: &[Curve; 3], w: &Curve) -> DVec3 {
    let c = camera_sum(curves, |l| w.eval_one(l) as f64);
    DVec3::new(c.y / c.x, 1.0, c.y / c.z)
}

/// The least-squares camera-RGB → XYZ matrix (module docs); `w` is the white-balance
/// illuminant (or D65), `m` the multipliers, `d65` the target illuminant.
pub fn fit_matrix(curves: &[Curve; 3], m: DVec3, w: &Curve, d65: &Curve, cmf: &Cmf) -> DMat3 {
    let norm_cam = camera_sum(curves, |l| w.eval_one(l) as f64).y;
    let xyz_of = |s: &dyn Fn(f32) -> f64| {
        let v = [0, 1, 2].map(|k| sum_nm(|l| s(l) * cmf.eval(l)[k] as f64));
        DVec3::from_array(v)
    };
    let norm_xyz = xyz_of(&|l| d65.eval_one(l) as f64).y;
    let (mut a, mut b) = (DMat3::ZERO, DMat3::ZERO);
    for rho in colorchecker() {
        let rgb = m * camera_sum(curves, |l| (rho.eval_one(l) * w.eval_one(l)) as f64) / norm_cam;
        let xyz = xyz_of(&|l| (rho.eval_one(l) * d65.eval_one(l)) as f64) / norm_xyz;
        a += outer(xyz, rgb);
        b += outer(rgb, rgb);
    }
    a * b.inverse()
}

fn outer(u: DVec3, v: DVec3) -> DMat3 {
    DMat3::from_cols(u * v.x, u * v.y, u * v.z)
}

/// The range the exposure factor must lie in: a real camera's runs from ~1e-10 (ISO 50,
/// 1 µs, f/64) to ~1e6 (ISO 1e6, 30 s, f/0.5); beyond 1e15 a radiance of 1e23 overflows f32,
/// below 1e-15 every channel underflows to 0.
pub const EXPOSURE_RANGE: (f64, f64) = (1e-15, 1e15);

/// The exposure factor k = (ISO/100) · t · π / (4 N²) (module docs).
pub fn exposure_scale(iso: f64, shutter: f64, f_number: f64) -> f64 {
    iso / 100.0 * shutter * std::f64::consts::PI / (4.0 * f_number * f_number)
}

/// What the camera channels' values are (the EXR header's `prism:cameraUnits`, the sidecar's
/// `sensor.camera.units`): the module docs' formula with the header's own factors.
pub const UNITS: &str = "camera.R/G/B = k * m_c * integral(L * c_c dlambda) / integral(g dlambda), with L the spectral radiance reaching the pixel (W m^-2 sr^-1 nm^-1), c_c the camera's curve of channel c, g its green curve, m the white-balance multipliers (prism:whiteBalance; 1 when off) and k the exposure factor (prism:exposureScale) = (ISO/100) * t * pi / (4 N^2) in s, or 1 without an exposure: a spectrally flat radiance of 1 reads G = k, and the white-balance illuminant reads R = G = B. With an exposure the values are ISO-scaled green-weighted radiant exposure on the sensor (J m^-2 nm^-1); corrected.R/G/B is prism:cameraToXYZ times them, in prism:correctedSpace";

/// A camera ready to develop its accumulated channels.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraModel {
    pub name: String,
    /// White-balance multipliers (1, 1, 1 when off).
    pub white_balance: Vec3,
    pub exposure: f32,
    /// White-balanced camera RGB → XYZ.
    pub to_xyz: Mat3,
    /// The colour-corrected layer's space.
    pub corrected: RgbSpace,
}

impl CameraModel {
    /// From per-pixel C (module docs): the camera layer k·m∘C and the colour-corrected layer
    /// (the output space's RGB of M·k·m∘C).
    pub fn develop(&self, c: &[Vec3]) -> (Vec<Vec3>, Vec<Vec3>) {
        let shown: Vec<Vec3> = c
            .iter()
            .map(|v| *v * self.white_balance * self.exposure)
            .collect();
        let m = self.corrected.from_xyz() * self.to_xyz;
        let corrected = shown.iter().map(|v| m * *v).collect();
        (shown, corrected)
    }

    /// EXR header attributes: name, matrix (row-major), multipliers, exposure factor.
    pub fn header(&self) -> Vec<(String, String)> {
        let r = self.to_xyz.transpose().to_cols_array();
        let nums = |v: &[f32]| {
            v.iter()
                .map(|x| format!("{x:e}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        vec![
            ("prism:camera".into(), self.name.clone()),
            ("prism:cameraToXYZ".into(), nums(&r)),
            (
                "prism:whiteBalance".into(),
                nums(&self.white_balance.to_array()),
            ),
            ("prism:exposureScale".into(), format!("{:e}", self.exposure)),
            ("prism:cameraUnits".into(), UNITS.into()),
            (
                "prism:correctedSpace".into(),
                format!("{:?}", self.corrected),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_camera_loads() {
        for name in CAMERAS {
            let c = named(name).unwrap_or_else(|| panic!("{name}"));
            let (lo, hi) = c[1].support().unwrap();
            assert!(lo <= 400.0 && hi >= 680.0, "{name}: {lo}-{hi}");
        }
        assert!(named("nikon_d8100").is_none());
        assert_eq!(colorchecker().len(), 24);
    }

    /// With white balance, the fitted matrix maps the white patch's camera RGB close to D65's
    /// XYZ (within 3%: a 3×3 fit cannot be exact on 24 patches, but neutrals are well served).
    #[test]
    fn matrix_maps_white_near_d65() {
        let cam = named("nikon_d810").unwrap();
        let d65 = data::named_illuminant("D65").unwrap();
        let a = data::named_illuminant("A").unwrap();
        let m = white_balance(&cam, &a);
        let fit = fit_matrix(&cam, m, &a, &d65, crate::spectrum::color::cie1931());
        let xyz = fit * DVec3::ONE;
        let d65_xyz = DVec3::new(0.3127 / 0.329, 1.0, (1.0 - 0.3127 - 0.329) / 0.329);
        assert!(
            ((xyz - d65_xyz) / d65_xyz).abs().max_element() < 0.03,
            "{xyz}"
        );
    }
}
