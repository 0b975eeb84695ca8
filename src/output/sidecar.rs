//! The sidecar `OUT.json` beside `OUT.exr`: everything a vision pipeline needs to use the
//! render without reading prism's code: the camera in OpenCV's and OpenGL's conventions, the
//! render settings, the sensor and every object with its id, 2D box and visible pixels.
//! Schema: docs/sidecar.md. Written atomically, after the EXR.

use crate::camera::Camera;
use crate::error::Error;
use crate::integrator::aov::Hit;
use crate::integrator::RenderStats;
use crate::load::Job;
use crate::math::portable;
use glam::{DMat3, DMat4};
use serde_json::{json, Value};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The sidecar's path for an EXR path: the same name with `.json`.
pub fn path_for(exr: &Path) -> PathBuf {
    exr.with_extension("json")
}

fn rows3(m: &DMat3) -> Value {
    json!((0..3).map(|r| m.row(r).to_array()).collect::<Vec<_>>())
}

fn rows4(m: &DMat4) -> Value {
    json!((0..4).map(|r| m.row(r).to_array()).collect::<Vec<_>>())
}

/// The camera block: K and distortion in OpenCV's pixel convention, R, t, OpenGL's pose.
pub fn camera(cam: &Camera, width: u32, height: u32) -> Value {
    let [fx, fy, cx, cy] = cam.intrinsics().k_opencv();
    let (r, t) = cam.world_to_opencv();
    let mut w2c = DMat4::from_mat3(r);
    w2c.w_axis = t.extend(1.0);
    let d = cam.distortion().copied().unwrap_or_default();
    let mut v = json!({
        "model": cam.model(),
        "image_size": [width, height],
        "K": [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]],
        "dist": [d.k1, d.k2, d.p1, d.p2, d.k3],
        "pixel_convention": "OpenCV: pixel (i, j) has its centre at (i, j); prism's film coordinates are OpenCV's + 0.5",
        "R": rows3(&r),
        "rvec": cam.rvec_opencv().to_array(),
        "t": t.to_array(),
        "world_to_camera_opencv": rows4(&w2c),
        "camera_to_world_opengl": rows4(&cam.camera_to_world_opengl()),
        "camera_to_world_prism": rows4(&cam.to_world().m.as_dmat4()),
        "position": cam.position().to_array(),
        "near": cam.near_clip(),
        "far": cam.far_clip(),
    });
    match cam {
        Camera::Orthographic(_) => {
            v["K_meaning"] = json!("orthographic: u = fx·x_cam + cx, v = fy·y_cam + cy (x_cam, y_cam in scene units, OpenCV camera frame)");
        }
        _ => {
            let k = cam.intrinsics();
            v["fov_deg"] = json!([
                2.0 * portable::atan(k.tan_half.x as f64).to_degrees(),
                2.0 * portable::atan(k.tan_half.y as f64).to_degrees()
            ]);
        }
    }
    if let Camera::ThinLens(l) = cam {
        v["aperture_radius"] = json!(l.aperture_radius);
        v["focus_distance"] = json!(l.focus_distance);
    }
    v
}

/// Every file the scene reads: each string in the config naming an existing file (relative to
/// the scene's folder), with its SHA-256; and a SHA-256 over the scene file and all of them.
fn hashes(job: &Job, scene_file: &Path) -> (Value, String) {
    let base = scene_file.parent().unwrap_or(Path::new("."));
    let mut files = std::collections::BTreeSet::new();
    fn walk(v: &Value, base: &Path, out: &mut std::collections::BTreeSet<PathBuf>) {
        match v {
            Value::String(s) => {
                let p = base.join(s);
                if !s.is_empty() && p.is_file() {
                    out.insert(p);
                }
            }
            Value::Array(a) => a.iter().for_each(|x| walk(x, base, out)),
            Value::Object(o) => o.values().for_each(|x| walk(x, base, out)),
            _ => {}
        }
    }
    if let Ok(v) = serde_json::to_value(&job.config) {
        walk(&v, base, &mut files);
    }
    // And every file the load read that the config does not name itself: a glTF's buffers and
    // images, the curve files a sensor file names, spectrum files.
    let normal = crate::io::paths::normal;
    let mut known: std::collections::BTreeSet<PathBuf> = files.iter().map(|p| normal(p)).collect();
    known.insert(normal(scene_file));
    for p in &job.inputs {
        if p.is_file() && known.insert(normal(p)) {
            files.insert(p.clone());
        }
    }
    let sha = |p: &Path| -> String {
        std::fs::read(p)
            .map(|b| format!("{:x}", Sha256::digest(&b)))
            .unwrap_or_else(|_| "unreadable".into())
    };
    let mut all = Sha256::new();
    // A glTF rendered directly names itself as its shape: hashed once.
    let scene_sha = sha(scene_file);
    all.update(scene_sha.as_bytes());
    let list: Vec<Value> = files
        .iter()
        .map(|p| {
            let h = if p == scene_file {
                scene_sha.clone()
            } else {
                sha(p)
            };
            all.update(h.as_bytes());
            json!({"path": p, "sha256": h})
        })
        .collect();
    (json!(list), format!("{:x}", all.finalize()))
}

/// Writes the sidecar for a finished render.
pub fn write(
    path: &Path,
    job: &Job,
    scene_file: &Path,
    exr: &Path,
    hits: Option<&[Option<Hit>]>,
    stats: &RenderStats,
    seconds: f64,
) -> Result<(), Error> {
    let v = value(job, scene_file, exr, hits, stats, seconds);
    let text = serde_json::to_string_pretty(&v).map_err(|e| Error::Other(e.to_string()))?;
    super::write_atomic(path, |tmp| {
        std::fs::write(tmp, text.as_bytes()).map_err(|e| e.to_string())
    })
}

/// The sidecar's JSON (`prism dataset` adds the frame's sampled parameters to it). `hits`:
/// the pixel-centre hits, when the render traced them; without them the objects have no
/// `bbox` or `visible_pixels`.
pub fn value(
    job: &Job,
    scene_file: &Path,
    exr: &Path,
    hits: Option<&[Option<Hit>]>,
    stats: &RenderStats,
    seconds: f64,
) -> Value {
    let s = &job.settings;
    let (w, h) = (s.width, s.height);
    // 2D boxes and visible pixels from the pixel-centre ids (the instance layer's).
    let n = job.objects.list.len();
    let mut boxes = vec![[u32::MAX, u32::MAX, 0, 0]; n];
    let mut pixels = vec![0u64; n];
    for (i, hit) in hits.unwrap_or_default().iter().enumerate() {
        if let Some(hit) = hit {
            let (x, y) = (i as u32 % w, i as u32 / w);
            // The object of the shape (a one-object glTF's parts share one).
            let k = job.objects.of_shape[hit.shape as usize];
            let b = &mut boxes[k];
            *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            pixels[k] += 1;
        }
    }
    let objects: Vec<Value> = job
        .objects
        .list
        .iter()
        .enumerate()
        .map(|(k, o)| {
            let mut v = json!({
                "instance_id": o.instance_id,
                "name": o.name,
                "label": o.label,
                "label_id": o.label_id,
                "material": o.material,
                "material_id": o.material_id,
                "to_world": rows4(&o.to_world.as_dmat4()),
                "bounds": {"min": o.bounds.0.to_array(), "max": o.bounds.1.to_array()},
            });
            if hits.is_some() {
                v["bbox"] = json!((pixels[k] > 0).then_some(boxes[k]));
                v["visible_pixels"] = json!(pixels[k]);
            }
            v
        })
        .collect();
    let (lo, hi) = s.wavelengths.range();
    let c = &job.channels;
    let layers = &c.sensor.layers;
    let bands = c.sensor.bands().map(|b| {
        json!({
            "count": b.count,
            "range_nm": [b.lo, b.hi],
            "width_nm": b.width(),
            "bands": (0..b.count).map(|i| json!({
                "channel": c.sensor.band_name(i),
                "center_nm": b.center(i),
                "range_nm": [b.lo + i as f32 * b.width(), b.lo + (i + 1) as f32 * b.width()],
            })).collect::<Vec<_>>(),
        })
    });
    let (files, scene_hash) = hashes(job, scene_file);
    // Every sensor of the render (the main one first, unnamed) and the EXR channels it wrote.
    fn sensors(s: &crate::sensor::Sensor) -> Value {
        let main = json!({"name": Value::Null, "prefix": "", "channels": s.own_channel_names()});
        let extras = s.extras().iter().map(|e| {
            json!({
                "name": e.name,
                "prefix": format!("{}.", e.name),
                "channels": e.sensor.own_channel_names().iter().map(|c| format!("{}.{c}", e.name)).collect::<Vec<_>>(),
                "attributes": e.sensor.layers.header.iter().map(|(k, v)| (k.clone(), Value::from(v.clone()))).collect::<serde_json::Map<_, _>>(),
            })
        });
        Value::Array(std::iter::once(main).chain(extras).collect())
    }
    let aov_list: Vec<Value> = job
        .aovs
        .iter()
        .map(|a| {
            json!({
                "name": a.name(),
                // Every sensor's, as `pipeline::add_layers` writes them.
                "channels": match a {
                    crate::film::Aov::Stderr => c.sensor.stderr_names(),
                    crate::film::Aov::Albedo => c.sensor.albedo_names(),
                    _ => a.channels().iter().map(|c| format!("{}.{c}", a.name())).collect(),
                },
                "type": if a.is_id() { "uint32" } else { "float32" },
                "meaning": a.description(),
            })
        })
        .collect();
    let mut v = json!({
        "format": "prism-sidecar",
        "version": 1,
        "image": exr.file_name().map(|f| f.to_string_lossy().into_owned()),
        "width": w,
        "height": h,
        "camera": camera(&job.scene.camera, w, h),
        "sensor": {
            // The sensor's own description, as its EXR header attributes carry it (observer,
            // camera, white balance, camera-to-XYZ matrix, exposure scale).
            "attributes": layers.header.iter().map(|(k, v)| (k.clone(), Value::from(v.clone()))).collect::<serde_json::Map<_, _>>(),
            "colour_channels": {"rgb": layers.rgb.iter().map(|r| format!("{r:?}")).collect::<Vec<_>>(), "xyz": layers.xyz},
            "response_channels": layers.responses.iter().map(|r| c.sensor.response_name(r)).collect::<Vec<_>>(),
            "units": "spectral radiance, W m^-2 sr^-1 nm^-1 (bands: mean over the band); XYZ and RGB: the CMF-weighted integral with Y of a unit constant spectrum = 1",
            "bands": bands,
            "exposure": Value::Null,
            "camera": layers.camera.as_ref().map(|m| json!({
                "name": m.name,
                "scale": m.exposure,
                "white_balance": m.white_balance.to_array(),
                "units": crate::sensor::camera::UNITS,
            })),
        },
        "sensors": sensors(&c.sensor),
        "render": {
            "prism_version": env!("CARGO_PKG_VERSION"),
            "scene_file": scene_file,
            "scene_sha256": scene_hash,
            "files": files,
            "spp": crate::config::Spp::of(s),
            "seed": s.seed,
            "sampler": format!("{:?}", s.sampler),
            "wavelengths": {"per_path": s.lanes, "sampling": format!("{:?}", s.wavelengths.kind()), "range_nm": [lo, hi]},
            "integrator": {"type": "path", "max_depth": s.path.max_depth, "rr_depth": s.path.rr_depth, "hide_emitters": s.path.hide_emitters, "clamp": s.path.clamp, "caustics": s.path.caustics.is_some()},
            "samples": stats.samples,
            "invalid_samples": stats.invalid_samples,
            "seconds": seconds,
        },
        "aovs": aov_list,
        "aov_conventions": "geometry and ids from one ray through each pixel centre; alpha filtered like radiance; background: distance/depth +inf, vectors 0, ids 0; camera-frame normals in OpenCV's frame",
        "labels": job.objects.labels.iter().enumerate().map(|(i, l)| json!({"id": i + 1, "name": l})).collect::<Vec<_>>(),
        "materials": job.objects.materials.iter().enumerate().map(|(i, m)| json!({"id": i + 1, "name": m})).collect::<Vec<_>>(),
        "objects": objects,
    });
    if let Some(f) = &job.flow {
        v["flow"] = flow(f, w, h);
    }
    v
}

/// The flow layers' frames: this frame's time, the step and the cameras at the neighbouring
/// frames (with their K, R and t `cv2.projectPoints` takes; docs/sidecar.md, "Flow").
fn flow(f: &crate::integrator::flow::FlowScene, w: u32, h: u32) -> Value {
    use crate::film::Dir;
    json!({
        "time": f.time,
        "fps": 1.0 / f.step,
        "step": f.step,
        "forward_time": f.time_of(Dir::Forward),
        "backward_time": f.time_of(Dir::Backward),
        "camera_forward": camera(&f.forward, w, h),
        "camera_backward": camera(&f.backward, w, h),
        "conventions": "flow_*: pixels, OpenCV image axes (x right, y down), from this frame's pixel centre (i, j) to where the same surface point projects at the other frame: (i + X, j + Y); scene_flow_*: p(t') - p(t) in the world frame, and (R' p' + t') - (R p + t) in OpenCV camera frames (each time's own camera); *_occlusion: 1 where the point is hidden at t', leaves the image or there is no surface",
    })
}
