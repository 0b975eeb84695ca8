//! `prism probe-bsdf`: a material's BSDF values at given directions, for checking prism against
//! independent implementations (tools/tests/test_principled.py checks the glTF model this way).
//!
//! Reads lines `wi.x wi.y wi.z wo.x wo.y wo.z` (local shading frame, z = normal, both pointing
//! away from the surface) from stdin and prints, per line, f(wi, wo)·|cos θo| at each requested
//! wavelength followed by the sampling density pdf(wi, wo) (solid angle) at the first one.

use crate::bsdf::BsdfLike;
use crate::error::{Error, InputError};
use crate::interaction::SurfaceInteraction;
use crate::math::Frame;
use crate::spectrum::Wavelengths;
use glam::{Vec2, Vec3};
use std::io::{BufRead, Write};
use std::path::Path;

/// Evaluates material `name` of `scene` for each direction pair on `input`, writing to `out`.
pub fn probe(
    scene: &Path,
    name: &str,
    lambdas: &[f32],
    input: impl BufRead,
    mut out: impl Write,
) -> Result<(), Error> {
    let job = crate::load::load(scene, |_| {})?;
    let index = job
        .config
        .materials
        .keys()
        .position(|k| k == name)
        .ok_or_else(|| {
            InputError::new(scene, format!("no material named \"{name}\""))
                .field("materials")
                .hint("--material names one of the scene's materials")
        })?;
    let material = &job.scene.materials[index];
    let si = SurfaceInteraction {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::from_normal(Vec3::Z),
        uv: Vec2::splat(0.5),
        t: 1.0,
        shape: 0,
        prim: 0,
        time: 0.0,
        bary: glam::Vec2::ZERO,
    };
    let io = |e: std::io::Error| Error::Other(format!("probe-bsdf: {e}"));
    for (n, line) in input.lines().enumerate() {
        let line = line.map_err(io)?;
        let v: Vec<f32> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|e| Error::Other(format!("stdin line {}: {e}", n + 1)))?;
        if v.is_empty() {
            continue;
        }
        if v.len() != 6 {
            return Err(Error::Other(format!(
                "stdin line {}: expected 6 numbers (wi, wo), got {}",
                n + 1,
                v.len()
            )));
        }
        let wi = Vec3::new(v[0], v[1], v[2]);
        let wo = Vec3::new(v[3], v[4], v[5]);
        let mut row = Vec::with_capacity(lambdas.len() + 1);
        for &l in lambdas {
            let wl = Wavelengths::<1> {
                lambda: [l],
                pdf: [1.0],
            };
            row.push(material.bsdf(&si, wi, &wl).eval(wi, wo)[0]);
        }
        let wl = Wavelengths::<1> {
            lambda: [lambdas[0]],
            pdf: [1.0],
        };
        row.push(material.bsdf(&si, wi, &wl).pdf(wi, wo));
        let text: Vec<String> = row.iter().map(|x| format!("{x:e}")).collect();
        writeln!(out, "{}", text.join(" ")).map_err(io)?;
    }
    Ok(())
}
