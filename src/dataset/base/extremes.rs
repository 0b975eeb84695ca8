//! Every variation's whole range against the scene's limits, at load (so at `--check`) and
//! before any frame (issue 27 item 7): a value some frame could draw that the scene loader
//! refuses (a camera beyond the 32-bit extent or looking along its up vector, a light past the
//! radiance limit, an IOR or roughness the material refuses, a film larger than memory) is
//! refused naming the dataset config's field and its fix, not found frame by frame as exit 1
//! blaming the base scene. The loader itself judges each extreme (`probe`): the base scene, its
//! meshes stood in for by unit spheres as `load::relight` does, built with the extreme applied;
//! the camera's positions and directions are checked over the whole range first (`shell`).

use super::{Base, LightRef};
use crate::config::sensor::{SensorField, SensorFile};
use crate::config::{SceneConfig, ShapeKind, SpectrumConfig, TransformOp};
use crate::dataset::apply::{self, EmitterSlot};
use crate::dataset::config::{LookAtVariation, Range};
use crate::error::InputError;
use crate::load::extent::MAX_COORD;
use crate::math::portable;
use crate::spectrum::Curve;
use glam::Vec3;
use std::path::Path;

/// How a light variation's extreme rewrites the light's spectrum.
type Respectrum = Box<dyn Fn(&SpectrumConfig) -> SpectrumConfig>;

impl Base {
    /// The checks of every variation's extremes; the first failing one is the error.
    pub(super) fn check_extremes(&self) -> Result<(), InputError> {
        let c = &self.config;
        // The film of every frame, with the scene's sensor and each one the variation draws.
        let film = "outputs.resolution";
        self.probe(film, "with the scene's sensor", |_| {})?;
        let dir = self.file.parent().unwrap_or(Path::new("."));
        for (i, f) in c
            .sensor
            .iter()
            .flat_map(|s| s.files.iter().flatten())
            .enumerate()
        {
            let p = crate::dataset::plan::absolute(&dir.join(f));
            self.probe(&format!("sensor.files[{i}]"), &format!("`{f}`"), |s| {
                s.sensor = Some(SensorField::File(SensorFile::File(p)));
                s.outputs = Default::default();
            })?;
        }
        if let Some(cam) = &c.camera {
            let up = Vec3::from(cam.up);
            if !(up.is_finite() && up.length() > 0.0) {
                return Err(self
                    .err(
                        "camera.up",
                        format!("the up vector {:?} is not a finite non-zero vector", cam.up),
                    )
                    .hint("give the world's up direction, e.g. up: (0, 1, 0)"));
            }
            let mut poses = Vec::new();
            match &cam.look_at {
                Some(LookAtVariation::Shell {
                    target,
                    radius,
                    elevation,
                    azimuth,
                }) => {
                    self.shell(Vec3::from(*target), *radius, *elevation, *azimuth, up)?;
                    let t = Vec3::from(*target);
                    poses.push((
                        crate::dataset::vary::shell_point(t, radius.1, elevation.1, azimuth.1),
                        t,
                    ));
                }
                Some(LookAtVariation::Poses(list)) => {
                    for (i, p) in list.iter().enumerate() {
                        let f = format!("camera.look_at[{i}]");
                        let (o, t) = (Vec3::from(p.origin), Vec3::from(p.target));
                        self.pose(&f, o, t, up)?;
                        poses.push((o, t));
                    }
                    poses.truncate(1);
                }
                None => {}
            }
            // The camera model's own checks (thin lens, intrinsics) at the fov's ends.
            let fovs = cam
                .fov
                .map_or(vec![None], |(lo, hi)| vec![Some(lo), Some(hi)]);
            for fov in fovs {
                let value = fov.map_or(String::new(), |f| format!("(fov {f})"));
                self.probe("camera", &value, |s| {
                    if let Some(f) = fov {
                        s.camera.fov = f;
                    }
                    if let Some((o, t)) = poses.first() {
                        s.camera.to_world = vec![TransformOp::LookAt {
                            origin: o.to_array(),
                            target: t.to_array(),
                            up: cam.up,
                        }];
                    }
                })?;
            }
        }
        for (k, l) in c.lights.iter().enumerate() {
            let r = self.light(&l.target, "lights")?;
            let hi = l.intensity.map_or(1.0, |x| x.1);
            let f = format!("lights[{k}]");
            let mut spectra: Vec<(String, Respectrum)> = Vec::new();
            if let Some((t0, t1)) = l.temperature {
                for t in [t0, t1] {
                    let y = Curve::blackbody(t).luminance();
                    spectra.push((
                        format!("(intensity {hi}, temperature {t} K)"),
                        Box::new(move |_| {
                            SpectrumConfig::Scaled(hi / y, Box::new(SpectrumConfig::Blackbody(t)))
                        }),
                    ));
                }
            } else if !l.illuminants.is_empty() {
                for n in &l.illuminants {
                    let n = n.clone();
                    spectra.push((
                        format!("(intensity {hi}, illuminant {n})"),
                        Box::new(move |_| {
                            SpectrumConfig::Scaled(hi, Box::new(SpectrumConfig::Named(n.clone())))
                        }),
                    ));
                }
            } else {
                spectra.push((
                    format!("(intensity {hi})"),
                    Box::new(move |old: &SpectrumConfig| {
                        SpectrumConfig::Scaled(hi, Box::new(old.clone()))
                    }),
                ));
            }
            let field = if l.temperature.is_some() || l.illuminants.is_empty() {
                format!("{f}.intensity")
            } else {
                format!("{f}.illuminants")
            };
            for (value, new) in &spectra {
                self.probe(&field, value, |s| match r {
                    LightRef::Shape(i) => {
                        if let Some(e) = s.shapes[i].emitter.as_mut() {
                            e.radiance = new(&e.radiance);
                        }
                    }
                    LightRef::Emitter(i) => match apply::emitter_slot(&mut s.emitters[i]) {
                        EmitterSlot::Spectrum(x) => *x = new(x),
                        EmitterSlot::Scale(x) => *x *= hi,
                    },
                })?;
            }
        }
        for (k, m) in c.materials.iter().enumerate() {
            let f = format!("materials[{k}]");
            for (what, range) in [("roughness", m.roughness), ("ior", m.ior)] {
                let Some((lo, hi)) = range else { continue };
                for v in [lo, hi] {
                    self.probe(&format!("{f}.{what}"), &format!("({v})"), |s| {
                        if let Some(mat) = s.materials.get_mut(&m.target) {
                            if what == "ior" {
                                apply::set_ior(mat, v);
                            } else {
                                apply::set_roughness(mat, v);
                            }
                        }
                    })?;
                }
            }
        }
        Ok(())
    }

    /// The largest intensity the light variations give emitter `k` (1 if none varies it).
    pub(super) fn max_intensity(&self, k: usize) -> f32 {
        let mine = |l: &&crate::dataset::config::LightVariation| matches!(self.light(&l.target, "lights"), Ok(LightRef::Emitter(e)) if e == k);
        self.config
            .lights
            .iter()
            .filter(mine)
            .fold(1.0, |a, l| a * l.intensity.map_or(1.0, |x| x.1))
    }

    /// The base scene as every frame has it (the dataset's spp and resolution), meshes that do
    /// not emit stood in for by unit spheres (their geometry is the built one), with `edit`
    /// applied, built: a refusal names `field`, the value and the loader's reason.
    fn probe(
        &self,
        field: &str,
        value: &str,
        edit: impl FnOnce(&mut SceneConfig),
    ) -> Result<(), InputError> {
        let mut s = self.scene.clone();
        if let Some(spp) = &self.config.outputs.spp {
            s.sampler.spp = *spp;
        }
        if let Some((w, h)) = self.config.outputs.resolution {
            s.film.width = w;
            s.film.height = h;
        }
        super::drop_flow_layers(&mut s.aovs);
        for sh in &mut s.shapes {
            if sh.emitter.is_none() && matches!(sh.shape, ShapeKind::Mesh { .. }) {
                sh.shape = ShapeKind::Sphere {
                    center: [0.0; 3],
                    radius: 1.0,
                };
                sh.to_world.clear();
                sh.animation = None;
            }
        }
        edit(&mut s);
        let Err(e) = crate::load::build(s, &self.scene_file) else {
            return Ok(());
        };
        let at = e.field.as_ref().map_or(String::new(), |f| format!("{f}: "));
        let hint = e
            .hint
            .as_ref()
            .map_or(String::new(), |h| format!(" (the scene's hint: {h})"));
        Err(self
            .err(
                field,
                format!(
                    "{field} {value}: a frame drawing it is refused by the scene `{}`: {at}{}",
                    self.scene_file.display(),
                    e.message
                ),
            )
            .hint(format!("narrow {field} to values the scene takes{hint}")))
    }

    /// A shell's whole range: the target finite, every camera position within the 32-bit
    /// extent and apart from the target, the view direction never along `up`.
    fn shell(
        &self,
        t: Vec3,
        radius: Range,
        el: Range,
        az: Range,
        up: Vec3,
    ) -> Result<(), InputError> {
        if !t.is_finite() {
            return Err(self
                .err(
                    "camera.look_at.target",
                    format!("the target {t} is not finite"),
                )
                .hint("give the point the camera looks at, e.g. target: (0, 0.8, 0)"));
        }
        let far = t.abs().max_element() + radius.1;
        if far > MAX_COORD {
            return Err(self
                .err("camera.look_at.radius", format!("a camera {} from the target reaches {far:e} from the origin, beyond {MAX_COORD:e}, the most prism's 32-bit geometry handles", radius.1))
                .hint("narrow the radius range (the scene's units are the shell's)"));
        }
        // Below ~10 ulps of the target the camera's position rounds onto the target.
        let near = 1e-6 * t.abs().max_element();
        if radius.0 <= near {
            return Err(self
                .err("camera.look_at.radius", format!("a radius of {} is too small beside a target {} from the origin: the camera would stand on the target", radius.0, t.abs().max_element()))
                .hint(format!("raise the radius range's lower end above {near:e}")));
        }
        // The direction from the target to the camera is ±up at one (elevation, azimuth).
        let u = up.normalize();
        for s in [1.0f32, -1.0] {
            let d = u * s;
            if d.y.abs() >= 1.0 {
                continue; // elevation ±90°, outside the checked (−89.9, 89.9)
            }
            let e = portable::asin(d.y).to_degrees();
            let a = portable::atan2(d.x, d.z).to_degrees();
            let tol = 1e-3;
            let in_az = (-3..=3).any(|k| {
                let a = a + 360.0 * k as f32;
                a >= az.0 - tol && a <= az.1 + tol
            });
            if e >= el.0 - tol && e <= el.1 + tol && in_az {
                return Err(self
                    .err("camera.up", format!("the up vector {up} lies along the view direction of the shell's pose at elevation {e:.3}°, azimuth {a:.3}°, inside its ranges: that frame's look-at has no image plane"))
                    .hint("give an up vector the camera never looks along (e.g. (0, 1, 0), which elevations within ±89.9° never meet), or narrow the elevation and azimuth ranges"));
            }
        }
        Ok(())
    }

    /// One pose: finite, within the extent, origin apart from target, not looking along `up`.
    fn pose(&self, f: &str, o: Vec3, t: Vec3, up: Vec3) -> Result<(), InputError> {
        let look = TransformOp::LookAt {
            origin: o.to_array(),
            target: t.to_array(),
            up: up.to_array(),
        };
        let ok = o.is_finite()
            && t.is_finite()
            && crate::load::transform(&[look], &self.file, f).is_ok();
        if !ok {
            return Err(self
                .err(f, format!("the pose from {o} to {t} (up {up}) is not a camera: origin and target must be finite and distinct, and the view direction not along the up vector"))
                .hint("move the origin off the target, or change camera.up"));
        }
        crate::load::extent::check_point(o.abs().max(t.abs()), &self.file, f, "the pose")
    }
}
