//! `prism export`: the fully resolved scene, as prism will render it, for other tools (the
//! Mitsuba 3 comparison in `tools/` reads it; there is no second RON parser anywhere).
//!
//! Everything is resolved: defaults filled in, every spectrum tabulated (`{"type":"irregular",
//! "wavelengths":[..], "values":[..]}` or `{"type":"constant","value":v}`; RGB already uplifted),
//! every triangle mesh (rectangles and cubes included) written in world space as a binary PLY
//! next to the JSON. Layout (all matrices 4×4 row-major, lengths in scene units):
//!
//! ```text
//! { "format": "prism-scene", "version": 1, "source": path,
//!   "camera": {"model", "to_world", "fov_x_deg", "fov_y_deg", "principal_point_offset_px",
//!              "near_clip", "far_clip"},
//!   "film": {"width", "height", "filter": {"type": "box", "radius"} | {"type": "gaussian", "stddev"}},
//!   "sampler": {"type": "independent" | "sobol", "spp", "seed"},
//!   "integrator": {"type": "path", "max_depth", "rr_depth", "hide_emitters", "clamp": null | radiance,
//!                  "caustics": null | {"light_paths", "bright_ratio", "max_roughness", "area_lights"}},
//!   "spectral": {"wavelengths", "range": [lo, hi], "sampling", "dispersion"},
//!   "outputs": {"rgb", "xyz", "bands": null | {"count", "range"}},
//!   "sensor": {"channels": [{"name", "srf": spectrum, "gain"}...]} (src/sensor/export.rs),
//!   "materials": [material...], "shapes": [shape...], "emitters": [emitter...] }
//! material: {"type": "diffuse", "reflectance": texture} | {"type": "twosided", "front", "back"}
//!   | {"type": "blend", "weight": float_texture, "bsdf0", "bsdf1"} | {"type": "mask", "opacity", "bsdf"}
//!   | {"type": "plastic" | "roughplastic", ...}
//!   | {"type": "dielectric" | "thindielectric" | "roughdielectric", "int_ior", "ext_ior",
//!      "dispersive", "specular_reflectance", "specular_transmittance"[, "distribution",
//!      "alpha_u", "alpha_v"]} | ...
//!   (a dielectric's int_ior and ext_ior are numbers, or spectra where "dispersive" is true)
//! texture: spectrum | {"type": "checkerboard", "color0", "color1", "uv_scale", "uv_offset"}
//!   | {"type": "bitmap", "filename", "raw", "filter", "wrap", "uv_scale", "uv_offset"}
//! shape: {"type": "mesh", "filename", "has_normals", ...} | {"type": "sphere", "center", "radius"}
//!   | {"type": "disk", "to_world"}, each with "flip_normals", "material" (index), "emitter" (index or null)
//! emitter: {"type": "area", "shape", "radiance"} (radiance: a spectrum, or a textured light's
//!     {"type": "bitmap", "filename" (null for an image embedded in a glTF file), "raw", "filter",
//!     "wrap", "uv_scale", "uv_offset", "factor": [r, g, b]}: the image's linear RGB × factor, each
//!     texel uplifted as an illuminant) | {"type": "point", "position", "intensity"}
//!   | {"type": "constant", "radiance"}
//!   | {"type": "spot", "intensity", "cutoff_angle", "beam_width", "to_world"} (angles in degrees)
//!   | {"type": "directional", "direction" (the way the light travels, unit), "irradiance"}
//!   | {"type": "envmap", "filename" (absolute path of the source image: Mitsuba uplifts its RGB
//!     the same way), "scale", "to_world"}
//! ```

use crate::bsdf::{microfacet::Distribution, Material, Param};
use crate::emitter::{AreaRadiance, Emitter};
use crate::error::Error;
use crate::filter::Filter;
use crate::load::Job;
use crate::math::portable;
use crate::shape::{Mesh, Shape};
use crate::spectrum::{Curve, Ior, RelativeIor};
use crate::texture::{FloatTexture, SpectralTexture, TexFilter, UvMap, Wrap};
use glam::Mat4;
use serde_json::{json, Value};
use std::io::Write;
use std::path::Path;

/// The files `export` writes into `dir` (checked against the scene's inputs before).
pub fn planned_files(job: &Job, dir: &Path) -> Vec<std::path::PathBuf> {
    let meshes = job.scene.shapes.iter().enumerate();
    let meshes = meshes.filter(|(_, s)| matches!(s, Shape::Mesh(_) | Shape::Instance(_)));
    std::iter::once(dir.join("scene.json"))
        .chain(meshes.map(|(i, _)| dir.join("meshes").join(format!("{i:04}.ply"))))
        .collect()
}

/// Writes `dir/scene.json` and `dir/meshes/*.ply` for the scene file `scene_file`.
pub fn export(job: &Job, scene_file: &Path, dir: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(dir.join("meshes")).map_err(|e| Error::io(dir, e))?;
    let s = &job.settings;
    let (lo, hi) = s.wavelengths.range();
    let ctx = Ctx { lo, hi };
    let scene = &job.scene;
    let cam = &scene.camera;
    let mut shapes = Vec::new();
    for (i, shape) in scene.shapes.iter().enumerate() {
        let flat;
        let shape = match shape {
            // An instance is exported as its world-space copy.
            Shape::Instance(inst) => {
                flat = Shape::Mesh(inst.flatten());
                &flat
            }
            s => s,
        };
        let mut v = match shape {
            Shape::Instance(_) => unreachable!("flattened above"),
            Shape::Mesh(m) => {
                let file = dir.join("meshes").join(format!("{i:04}.ply"));
                write_ply(m, &file)?;
                json!({"type": "mesh", "filename": file.canonicalize().map_err(|e| Error::io(&file, e))?, "has_normals": !m.normals.is_empty(), "has_uvs": !m.uvs.is_empty()})
            }
            Shape::Sphere(sp) => {
                json!({"type": "sphere", "center": sp.center.to_array(), "radius": sp.radius, "flip_normals": sp.flip})
            }
            Shape::Disk(d) => {
                json!({"type": "disk", "to_world": rows(&d.to_world.m), "flip_normals": d.flip})
            }
        };
        v["material"] = json!(scene.shape_material[i]);
        v["emitter"] = json!(scene.shape_emitter[i]);
        shapes.push(v);
    }
    let out = json!({
        "format": "prism-scene",
        "version": 1,
        "source": scene_file.canonicalize().unwrap_or_else(|_| scene_file.to_path_buf()),
        "camera": {
            "model": cam.model(),
            "principal_point_offset_px": cam.intrinsics().offset.to_array(),
            "fov_y_deg": 2.0 * portable::atan(cam.tan_half_fov().y).to_degrees(),
            "to_world": rows(&cam.to_world().m),
            "fov_x_deg": 2.0 * portable::atan(cam.tan_half_fov().x).to_degrees(),
            "near_clip": cam.near_clip(),
            "far_clip": cam.far_clip(),
        },
        "film": {"width": s.width, "height": s.height, "filter": match &s.filter {
            Filter::Box { radius } => json!({"type": "box", "radius": radius}),
            Filter::Tabulated { radius, .. } => json!({"type": "gaussian", "stddev": radius / 4.0}),
        }},
        "sampler": {"type": format!("{:?}", s.sampler).to_lowercase(), "spp": s.spp, "seed": s.seed},
        "integrator": {"type": "path", "max_depth": s.path.max_depth, "rr_depth": s.path.rr_depth, "hide_emitters": s.path.hide_emitters, "clamp": s.path.clamp, "caustics": s.path.caustics},
        "spectral": {"wavelengths": s.lanes, "range": [lo, hi], "sampling": format!("{:?}", s.wavelengths.kind()).to_lowercase(), "dispersion": format!("{:?}", s.dispersion)},
        "outputs": {"rgb": job.channels.sensor.layers.rgb.contains(&crate::sensor::RgbSpace::Srgb), "xyz": job.channels.sensor.layers.xyz, "bands": job.channels.sensor.bands().map(|b| json!({"count": b.count, "range": [b.lo, b.hi]}))},
        "sensor": {"channels": crate::sensor::export::channels(&job.channels.sensor, lo, hi)},
        "materials": scene.materials.iter().map(|m| ctx.material(m)).collect::<Vec<_>>(),
        "shapes": shapes,
        "emitters": scene.emitters.iter().map(|e| ctx.emitter(e)).collect::<Vec<_>>(),
    });
    let file = dir.join("scene.json");
    let text = serde_json::to_string_pretty(&out).map_err(|e| Error::Other(e.to_string()))?;
    crate::output::write_atomic(&file, |tmp| {
        std::fs::write(tmp, text).map_err(|e| e.to_string())
    })
}

fn rows(m: &Mat4) -> [[f32; 4]; 4] {
    m.transpose().to_cols_array_2d()
}

struct Ctx {
    lo: f32,
    hi: f32,
}

impl Ctx {
    fn spectrum(&self, c: &Curve) -> Value {
        match c.tabulate(self.lo, self.hi) {
            None => json!({"type": "constant", "value": c.eval_one(0.5 * (self.lo + self.hi))}),
            Some((wl, v)) => json!({"type": "irregular", "wavelengths": wl, "values": v}),
        }
    }

    fn uv(map: &UvMap) -> (Value, Value) {
        (
            json!([map.scale.x, map.scale.y]),
            json!([map.offset.x, map.offset.y]),
        )
    }

    fn texture(&self, t: &SpectralTexture) -> Value {
        match t {
            SpectralTexture::Uniform(c) => self.spectrum(c),
            SpectralTexture::Checkerboard {
                color0,
                color1,
                map,
            } => {
                let (scale, offset) = Self::uv(map);
                json!({"type": "checkerboard", "color0": self.spectrum(color0), "color1": self.spectrum(color1), "uv_scale": scale, "uv_offset": offset})
            }
            SpectralTexture::Bitmap(g) => {
                let (scale, offset) = Self::uv(&g.map);
                let src = g.source.as_ref();
                json!({"type": "bitmap", "filename": src.map(|s| s.path.canonicalize().unwrap_or_else(|_| s.path.clone())), "raw": src.is_some_and(|s| s.raw),
                       "filter": filter_name(g.filter), "wrap": wrap_name(g.wrap), "uv_scale": scale, "uv_offset": offset})
            }
            // Vertex colours live on prism's meshes only (the exported meshes carry no colour
            // attribute): the texture under them is exported; scenes/README.md says so.
            SpectralTexture::Vertex(v) => self.texture(&v.base),
        }
    }

    fn float_texture(&self, t: &FloatTexture) -> Value {
        match t {
            FloatTexture::Constant(v) => json!({"type": "constant", "value": v}),
            FloatTexture::Checkerboard {
                value0,
                value1,
                map,
            } => {
                let (scale, offset) = Self::uv(map);
                json!({"type": "checkerboard", "value0": value0, "value1": value1, "uv_scale": scale, "uv_offset": offset})
            }
            FloatTexture::Bitmap(g) => {
                let (scale, offset) = Self::uv(&g.map);
                let src = g.source.as_ref();
                json!({"type": "bitmap", "filename": src.map(|s| s.path.canonicalize().unwrap_or_else(|_| s.path.clone())), "raw": src.is_some_and(|s| s.raw),
                       "filter": filter_name(g.filter), "wrap": wrap_name(g.wrap), "uv_scale": scale, "uv_offset": offset})
            }
            FloatTexture::Vertex(v) => self.float_texture(&v.base),
        }
    }

    /// A material by Mitsuba 3's plugin and parameter names, as the material lists them.
    fn material(&self, m: &Material) -> Value {
        let mut v = json!({});
        let kind = m.traverse(&mut |name, p| match p {
            Param::Ior(ior) => self.iors(ior, &mut v),
            p => v[name] = self.param(p),
        });
        v["type"] = json!(kind);
        v
    }

    fn param(&self, p: Param) -> Value {
        match p {
            Param::Texture(t) => self.texture(t),
            Param::Float(t) => self.float_texture(t),
            Param::Spectrum(c) => self.spectrum(c),
            Param::Number(x) => json!(x),
            Param::Bool(b) => json!(b),
            Param::Distribution(d) => json!(distribution_name(d)),
            Param::Bsdf(m) => self.material(m),
            Param::Ior(_) => unreachable!("written by `iors`, in `material`"),
        }
    }

    /// A dielectric's `int_ior` and `ext_ior`: numbers (as Mitsuba takes them) unless the
    /// interface is dispersive; then both are spectra (a constant side as `{"type": "constant"}`)
    /// and `"dispersive": true` tells the reader that Mitsuba cannot render it the same way.
    fn iors(&self, ior: &RelativeIor, out: &mut Value) {
        let mid = 0.5 * (self.lo + self.hi);
        let side = |n: &Ior| {
            if !ior.dispersive() {
                return json!(n.eval_one(mid));
            }
            match n.tabulate(self.lo, self.hi) {
                None => json!({"type": "constant", "value": n.eval_one(mid)}),
                Some((wl, v)) => json!({"type": "irregular", "wavelengths": wl, "values": v}),
            }
        };
        out["int_ior"] = side(&ior.int);
        out["ext_ior"] = side(&ior.ext);
        out["dispersive"] = json!(ior.dispersive());
    }

    fn emitter(&self, e: &Emitter) -> Value {
        match e {
            Emitter::Area(a) => match &a.radiance {
                AreaRadiance::Uniform(c) => {
                    json!({"type": "area", "shape": a.shape, "radiance": self.spectrum(c)})
                }
                // The image's RGB times `factor`, each texel uplifted as an illuminant.
                AreaRadiance::Textured(t) => {
                    let (wrap, filter, map) = t.placement();
                    let (scale, offset) = Self::uv(&map);
                    let src = t.source();
                    json!({"type": "area", "shape": a.shape, "radiance": {"type": "bitmap",
                        "filename": src.map(|s| s.path.canonicalize().unwrap_or_else(|_| s.path.clone())),
                        "raw": src.is_some_and(|s| s.raw), "filter": filter_name(filter), "wrap": wrap_name(wrap),
                        "uv_scale": scale, "uv_offset": offset, "factor": t.factor}})
                }
            },
            Emitter::Point {
                position,
                intensity,
            } => {
                json!({"type": "point", "position": position.to_array(), "intensity": self.spectrum(intensity)})
            }
            // Spot, directional and environment-map emitters.
            Emitter::Spot(s) => {
                let (cutoff, beam) = s.angles_deg();
                json!({"type": "spot", "intensity": self.spectrum(s.intensity()), "cutoff_angle": cutoff,
                       "beam_width": beam, "to_world": rows(&s.to_world())})
            }
            Emitter::Directional {
                direction,
                irradiance,
            } => {
                json!({"type": "directional", "direction": direction.to_array(), "irradiance": self.spectrum(irradiance)})
            }
            Emitter::Envmap(m) => {
                let src = m.source();
                json!({"type": "envmap", "filename": src.map(|s| s.path.canonicalize().unwrap_or_else(|_| s.path.clone())),
                       "scale": m.scale(), "to_world": rows(&Mat4::from_mat3(m.to_world()))})
            }
            Emitter::Constant { radiance } => {
                json!({"type": "constant", "radiance": self.spectrum(radiance)})
            }
            // A static scene: the light in its pose at the shutter's opening.
            Emitter::Moving(m) => self.emitter(&m.posed()),
            // Its shape is written as the scene holds it (object space), and so is the light.
            Emitter::MovingArea(m) => self.emitter(&Emitter::Area(m.area.clone())),
        }
    }
}

pub(crate) fn distribution_name(d: Distribution) -> &'static str {
    match d {
        Distribution::Beckmann => "beckmann",
        Distribution::Ggx => "ggx",
    }
}

fn filter_name(f: TexFilter) -> &'static str {
    match f {
        TexFilter::Bilinear => "bilinear",
        TexFilter::Nearest => "nearest",
    }
}

fn wrap_name(w: Wrap) -> &'static str {
    match w {
        Wrap::Repeat => "repeat",
        Wrap::Clamp => "clamp",
    }
}

/// A binary little-endian PLY with positions, optional normals and uvs, and triangles.
fn write_ply(m: &Mesh, path: &Path) -> Result<(), Error> {
    let mut out = Vec::new();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by prism export\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        m.positions.len()
    );
    if !m.normals.is_empty() {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if !m.uvs.is_empty() {
        header.push_str("property float u\nproperty float v\n");
    }
    header.push_str(&format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.indices.len()
    ));
    out.write_all(header.as_bytes()).unwrap();
    for i in 0..m.positions.len() {
        let mut vals = m.positions[i].to_array().to_vec();
        if !m.normals.is_empty() {
            vals.extend(m.normals[i].to_array());
        }
        if !m.uvs.is_empty() {
            vals.extend(m.uvs[i].to_array());
        }
        for v in vals {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    for tri in &m.indices {
        out.push(3);
        for &i in tri {
            out.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    crate::output::write_atomic(path, |tmp| {
        std::fs::write(tmp, &out).map_err(|e| e.to_string())
    })
}
