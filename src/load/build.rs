//! Config → render-ready scene and settings, with every check a user's mistake can trip
//! reported against the scene file and the field.

use super::check::check;
use super::{emitters, geometry, materials, Scene};
use crate::bsdf::{DiffuseParams, Material};
use crate::config::{self, SceneConfig};
use crate::emitter::{AreaEmitter, Emitter};
use crate::error::{Error, InputError};
use crate::filter::Filter;
use crate::integrator::RenderSettings;
use crate::sensor::FilmChannels;
use crate::spectrum::{Curve, WavelengthSampler};
use crate::texture::SpectralTexture;
use std::path::Path;

/// A scene ready to render, with its settings.
pub struct Job {
    pub scene: Scene,
    pub settings: RenderSettings,
    pub channels: FilmChannels,
    /// Things worth telling the user that do not stop the render.
    pub warnings: Vec<String>,
    /// The configuration it was built from (after command-line overrides).
    pub config: SceneConfig,
    /// Every file the load read (scene, meshes, images, spectra): outputs must not be one.
    pub inputs: Vec<std::path::PathBuf>,
    /// AOV layers to write (`aovs`), and the objects they and the sidecar name.
    pub aovs: Vec<crate::film::Aov>,
    pub objects: super::objects::Objects,
    /// What the flow layers need (`load::flow`), when `aovs` asks for one.
    pub flow: Option<crate::integrator::flow::FlowScene>,
}

/// Reads, checks and builds the scene file at `path`; `edit` may change the parsed config
/// first (command-line overrides).
pub fn load(path: &Path, edit: impl FnOnce(&mut SceneConfig)) -> Result<Job, Error> {
    let (job, inputs) = super::inputs::collect(|| -> Result<Job, Error> {
        if super::gltf::is_gltf(path) {
            let model = super::gltf::open(path)?;
            let (mut cfg, warnings) = super::gltf::scene_for(&model)?;
            let camera = cfg.camera.clone();
            edit(&mut cfg);
            // The file's camera follows its animation at the time the edits set (with an
            // open shutter, as the node chain's motion).
            let moving = super::gltf::animate_camera(&model, &camera, &mut cfg)?;
            let mut job =
                super::gltf::with_model(model, || build_moving(cfg, path, moving.as_ref()))?;
            job.warnings.splice(0..0, warnings);
            return Ok(job);
        }
        let mut cfg = config::parse_file(path)?;
        edit(&mut cfg);
        Ok(build(cfg, path)?)
    });
    Ok(Job { inputs, ..job? })
}

/// As `load`, from text (`file` names it in errors and anchors relative paths).
pub fn load_str(text: &str, file: &Path) -> Result<Job, Error> {
    let cfg = config::parse_str(text, file)?;
    Ok(build(cfg, file)?)
}

/// The longest wavelength a spectral range may reach, nm (100 µm: far infrared, beyond any
/// camera's response).
pub const MAX_NM: f32 = 1e5;

/// Builds a job from a parsed config.
pub fn build(cfg: SceneConfig, file: &Path) -> Result<Job, InputError> {
    build_moving(cfg, file, None)
}

/// As `build`, with the camera moved by `camera` rather than by `cfg.camera.animation` (a
/// glTF camera under animated nodes: `gltf::animate_camera`).
pub(super) fn build_moving(
    mut cfg: SceneConfig,
    file: &Path,
    camera: Option<&crate::motion::Motion>,
) -> Result<Job, InputError> {
    let mut warnings = Vec::new();
    // Flow first: it builds the scene over the neighbouring frames from the animations.
    let flow = super::flow::setup(&cfg, file, camera)?;
    // Time next: at an instant every animated transform becomes a static one.
    let plan = super::motion::prepare_moving(&mut cfg, file, camera)?;

    // Spectral settings come first: spectra are checked over the render's range.
    let range = super::settings::spectral_range(&cfg, file)?;
    let (sp, (lo, hi)) = (&cfg.spectral, range);
    let camera = super::settings::camera(&cfg, file)?;
    let f = &cfg.film;
    super::settings::check_integrator(&cfg, file)?;
    let s = &cfg.sampler;

    // Outputs: the sensor (or the older `outputs`).
    let main = crate::load::sensor::build(
        cfg.sensor.as_ref(),
        &cfg.outputs,
        file,
        range,
        &mut warnings,
    )?;
    let channels = FilmChannels {
        sensor: crate::load::sensor::with_extras(main, &cfg.sensors, file, range, &mut warnings)?,
    };

    // The film's memory, before meshes and textures load (again with the BVH below).
    let mut memory = crate::resources::Plan {
        width: f.width,
        height: f.height,
        slots: channels.sensor.slots(),
        // Every slot becomes a channel, and each RGB space three more.
        channels: channels.sensor.slots() + 3 * channels.sensor.layers.rgb.len(),
        caustics: cfg.integrator.caustics.is_some(),
        lanes: sp.wavelengths,
        threads: crate::resources::threads(),
        prims: 0,
    };
    crate::resources::check(&memory, file)?;

    // Materials (by name, in name order); a default grey diffuse is added if a shape needs one.
    let mut names: Vec<&String> = cfg.materials.keys().collect();
    let mut materials = Vec::new();
    for (name, m) in &cfg.materials {
        materials.push(materials::material(name, m, file, range, &mut warnings)?);
    }
    let mut default_material = None;
    // Parallel to `materials` and `shapes`: for the objects (sidecar, id AOVs).
    let mut material_names: Vec<String> = cfg.materials.keys().cloned().collect();
    let mut shape_source = Vec::new();

    // Shapes and their area emitters.
    let mut shapes = Vec::new();
    let mut shape_material = Vec::new();
    let mut shape_emitter = Vec::new();
    let mut emitters = Vec::new();
    let mut shape_name = Vec::new();
    let mut gltf_emitters = Vec::new();
    let base = file.parent().unwrap_or(Path::new("."));
    let mut mesh_files = super::instancing::MeshFiles::new(&cfg, base);
    let mut moving = Vec::new();
    for (i, sc) in cfg.shapes.iter().enumerate() {
        let field = format!("shapes[{i}]");
        let own = plan.as_ref().and_then(|p| p.shapes[i].as_ref());
        let gltf = matches!(sc.shape, config::ShapeKind::Gltf { .. });
        if let Some(m) = own.filter(|_| !gltf) {
            let obj = super::motion::object_space(sc, file, &field)?;
            moving.push((shapes.len() as u32, m.clone()));
            let shape = geometry::shape(&obj, file, &field, base, &mut warnings)?;
            super::extent::check_shape(&shape, file, &field)?;
            let mat = material_index(
                sc,
                &field,
                file,
                &names,
                &mut default_material,
                &mut materials,
                &mut material_names,
            )?;
            let at = (file, field.as_str(), range);
            let light =
                super::light_motion::area(sc, (&shape, shapes.len() as u32), m, at, &mut warnings)?;
            shape_emitter.push(light.map(|e| {
                emitters.push(e);
                (emitters.len() - 1) as u32
            }));
            shapes.push(shape);
            shape_material.push(mat);
            shape_name.push(None);
            shape_source.push(i);
            continue;
        }
        if let config::ShapeKind::Gltf { .. } = sc.shape {
            let inst = super::instancing::enabled(&cfg);
            let when = super::gltf::When {
                time: cfg.camera.shutter.map_or(0.0, |s| s.open),
                open: plan.is_some(),
                root: own.cloned(),
            };
            let ex = super::gltf::expand(
                sc,
                file,
                &field,
                base,
                &names,
                range,
                inst,
                when,
                &mut warnings,
            )?;
            super::gltf::add_shapes(
                ex,
                &mut materials,
                &mut shapes,
                &mut shape_material,
                &mut shape_emitter,
                &mut emitters,
                &mut shape_name,
                &mut material_names,
                &mut gltf_emitters,
                &mut moving,
            );
            shape_source.resize(shapes.len(), i);
            continue;
        }
        let shape = match mesh_files.instance(sc, file, &field, base, &mut warnings)? {
            Some(instance) => instance,
            None => {
                let shape = geometry::shape(sc, file, &field, base, &mut warnings)?;
                super::extent::check_shape(&shape, file, &field)?;
                shape
            }
        };
        let mat = material_index(
            sc,
            &field,
            file,
            &names,
            &mut default_material,
            &mut materials,
            &mut material_names,
        )?;
        let emitter = match &sc.emitter {
            Some(e) => {
                let f = format!("{field}.emitter.radiance");
                let radiance =
                    super::emission::area_radiance(&e.radiance, file, &f, range, &mut warnings)?;
                super::emission::check_shape(&radiance, &shape, file, &f)?;
                emitters.push(Emitter::Area(AreaEmitter::with_radiance(
                    shapes.len() as u32,
                    &shape,
                    radiance,
                )));
                Some((emitters.len() - 1) as u32)
            }
            None => None,
        };
        shapes.push(shape);
        shape_material.push(mat);
        shape_emitter.push(emitter);
        shape_name.push(None);
        shape_source.push(i);
    }
    names.clear();

    for (i, e) in cfg.emitters.iter().enumerate() {
        let field = format!("emitters[{i}]");
        let em = emitters::emitter(e, file, &field, range, &mut warnings)?;
        let motion = plan.as_ref().and_then(|p| p.lights[i].clone());
        let open = plan.as_ref().map_or(0.0, |p| p.shutter.open);
        emitters.push(super::light_motion::wrap(em, motion, open));
    }
    for (field, e, motion) in gltf_emitters {
        let em = emitters::emitter(&e, file, &field, range, &mut warnings)?;
        let open = plan.as_ref().map_or(0.0, |p| p.shutter.open);
        emitters.push(super::light_motion::wrap(em, motion, open));
    }
    if emitters.is_empty() {
        warnings.push(format!(
            "{}: the scene has no emitters; the image will be black",
            file.display()
        ));
    }

    let settings = RenderSettings {
        width: f.width,
        height: f.height,
        spp: s.spp.max(),
        adaptive: s.spp.adaptive(),
        seed: s.seed,
        sampler: s.kind,
        lanes: sp.wavelengths,
        wavelengths: match sp.sampling {
            // One cell per nm (at least 64) of the sensor's density (src/sensor/sampling.rs).
            crate::spectrum::WavelengthSampling::Sensor => {
                let cells = ((hi - lo).ceil() as usize).max(64);
                let d = channels.sensor.sampling_density((lo, hi), cells);
                WavelengthSampler::tabulated(lo, hi, &d)
            }
            k => WavelengthSampler::new(k, lo, hi),
        },
        filter: Filter::new(&f.filter),
        path: cfg.integrator,
        dispersion: cfg.spectral.dispersion,
        simd: Default::default(),
    };
    if let Some(a) = settings.adaptive {
        check(
            a.target != crate::config::ErrorTarget::Bands || channels.sensor.bands().is_some(),
            file,
            "sampler.spp.target",
            "target: Bands needs spectral bands in the sensor's output; use target: Y or add bands",
        )?;
    }
    check(
        cfg.accel.is_available(),
        file,
        "accel",
        "Embree is not available in this build of prism; rebuild with \
         `cargo build --release --features embree` (needs Embree 3, Debian: libembree-dev), \
         or use `accel: Bvh`",
    )?;
    memory.prims = super::instancing::unique_prims(&shapes);
    crate::resources::check(&memory, file)?;
    let motions = super::motion::motions(plan, moving, &cfg, (f.width, f.height), file)?;
    let mut scene = Scene::with_motion(
        camera,
        shapes,
        shape_material,
        shape_emitter,
        materials,
        emitters,
        cfg.accel,
        motions,
    );
    scene.shape_name = shape_name;
    let aovs = super::objects::aovs(&cfg.aovs, file)?;
    let objects = super::objects::objects(&cfg, &scene, file, &shape_source, material_names)?;
    Ok(Job {
        scene,
        settings,
        channels,
        warnings,
        config: cfg,
        inputs: Vec::new(),
        aovs,
        objects,
        flow,
    })
}

/// The index of shape `sc`'s material (a default grey diffuse, added once, if it names none).
fn material_index(
    sc: &config::ShapeConfig,
    field: &str,
    file: &Path,
    names: &[&String],
    default_material: &mut Option<u32>,
    materials: &mut Vec<Material>,
    material_names: &mut Vec<String>,
) -> Result<u32, InputError> {
    Ok(match &sc.material {
        Some(name) => match names.iter().position(|n| *n == name) {
            Some(k) => k as u32,
            None => {
                let list = if names.is_empty() {
                    "(none defined)".to_string()
                } else {
                    names
                        .iter()
                        .map(|n| format!("\"{n}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                return Err(
                    InputError::new(file, format!("unknown material \"{name}\""))
                        .field(format!("{field}.material"))
                        .hint(format!("the materials are: {list}")),
                );
            }
        },
        None => *default_material.get_or_insert_with(|| {
            materials.push(Material::Diffuse(DiffuseParams {
                reflectance: SpectralTexture::Uniform(Curve::Constant(0.5)),
            }));
            material_names.push("(default)".into());
            (materials.len() - 1) as u32
        }),
    })
}
