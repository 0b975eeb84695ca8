//! AOV layers ("arbitrary output variables"): what the first surface a camera ray meets is,
//! written beside the colour channels as `layer.channel` EXR channels.
//!
//! Conventions (scenes/README.md, "AOVs"; tested in `tests/aov.rs`):
//! - Geometry and ids come from one ray per pixel through the pixel centre (film position
//!   i + 0.5, the lens centre of a thin lens): exact values of one surface point, never a blend
//!   of a foreground and a background across an edge. `alpha` is filtered like radiance: the
//!   fraction of the pixel's camera samples (the very rays the colour channels used) that hit.
//! - Units are the scene's; `distance` is along the ray from the camera centre (the lens
//!   centre; the orthographic camera: from its film plane), `depth` is z along the optical
//!   axis. World-frame vectors are in the scene's frame; camera-frame normals in OpenCV's
//!   (x right, y down, z forward: n_cam = R·n_world with the sidecar's R).
//! - Background (no surface): `distance`, `depth` +inf; positions, normals, uv 0; ids 0.
//!   Instance ids are 1 + the shape's index in `shapes`, label ids 1 + the label's index in the
//!   sidecar's sorted `labels`, material ids 1 + the material's index in the sidecar's
//!   `materials`; 32-bit unsigned EXR channels.
//! - `albedo`: the material's diffuse reflectance at the pixel-centre hit (definition in
//!   `integrator::albedo`); background 0.
//! - `stderr`: each pixel's standard error of Y and of every band, √(s²/spp) with s² the
//!   unbiased variance of its camera samples' contributions (the colour channels are unchanged);
//!   under adaptive sampling, the achieved error of the estimate's samples (its pilot, the
//!   first `min`, included).
//! - `spp`: the number of camera samples each pixel's estimate averaged (32-bit unsigned; the
//!   scene's spp everywhere unless adaptive, whose pilot is in the count).
//! - Flow (`integrator::flow`; docs/sidecar.md, "Flow"): the surface point seen through the
//!   pixel centre at the frame time t, followed to the frame t ± step (`camera.fps`):
//!   `flow_*` in pixels on OpenCV's image axes (x right, y down), from this frame's pixel
//!   centre to where that point projects then; `scene_flow_*` its 3D displacement in the world
//!   and in OpenCV's camera frames (each time's own camera); `flow_*_occlusion` 1 where it is
//!   hidden then, leaves the frame, or there is no surface. Background: flows 0, occlusion 1.

/// The neighbouring frame a flow layer follows the surface point to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dir {
    /// The frame one step later (t + 1/fps).
    Forward,
    /// The frame one step earlier (t − 1/fps).
    Backward,
}

/// One AOV layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    Distance,
    Depth,
    Position,
    Normal,
    GeoNormal,
    NormalCamera,
    GeoNormalCamera,
    Uv,
    Instance,
    Label,
    Material,
    Alpha,
    Stderr,
    Albedo,
    Spp,
    /// Optical flow to the neighbouring frame, pixels.
    Flow(Dir),
    /// 1 where the point is hidden at the neighbouring frame or leaves it.
    FlowOcclusion(Dir),
    /// The point's displacement to the neighbouring frame, world frame.
    SceneFlow(Dir),
    /// The same in OpenCV's camera frames (each time's own camera).
    SceneFlowCamera(Dir),
}

impl Aov {
    pub const ALL: [Aov; 23] = [
        Aov::Distance,
        Aov::Depth,
        Aov::Position,
        Aov::Normal,
        Aov::GeoNormal,
        Aov::NormalCamera,
        Aov::GeoNormalCamera,
        Aov::Uv,
        Aov::Instance,
        Aov::Label,
        Aov::Material,
        Aov::Alpha,
        Aov::Stderr,
        Aov::Albedo,
        Aov::Spp,
        Aov::Flow(Dir::Forward),
        Aov::Flow(Dir::Backward),
        Aov::FlowOcclusion(Dir::Forward),
        Aov::FlowOcclusion(Dir::Backward),
        Aov::SceneFlow(Dir::Forward),
        Aov::SceneFlow(Dir::Backward),
        Aov::SceneFlowCamera(Dir::Forward),
        Aov::SceneFlowCamera(Dir::Backward),
    ];

    /// The name in `aovs: [...]` and `--aovs`, and the EXR layer's name.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Distance => "distance",
            Aov::Depth => "depth",
            Aov::Position => "position",
            Aov::Normal => "normal",
            Aov::GeoNormal => "geo_normal",
            Aov::NormalCamera => "normal_camera",
            Aov::GeoNormalCamera => "geo_normal_camera",
            Aov::Uv => "uv",
            Aov::Instance => "instance",
            Aov::Label => "label",
            Aov::Material => "material",
            Aov::Alpha => "alpha",
            Aov::Stderr => "stderr",
            Aov::Albedo => "albedo",
            Aov::Spp => "spp",
            Aov::Flow(Dir::Forward) => "flow_forward",
            Aov::Flow(Dir::Backward) => "flow_backward",
            Aov::FlowOcclusion(Dir::Forward) => "flow_forward_occlusion",
            Aov::FlowOcclusion(Dir::Backward) => "flow_backward_occlusion",
            Aov::SceneFlow(Dir::Forward) => "scene_flow_forward",
            Aov::SceneFlow(Dir::Backward) => "scene_flow_backward",
            Aov::SceneFlowCamera(Dir::Forward) => "scene_flow_forward_camera",
            Aov::SceneFlowCamera(Dir::Backward) => "scene_flow_backward_camera",
        }
    }

    /// The direction of a flow layer (None for the others).
    pub fn flow_dir(self) -> Option<Dir> {
        match self {
            Aov::Flow(d) | Aov::FlowOcclusion(d) | Aov::SceneFlow(d) | Aov::SceneFlowCamera(d) => {
                Some(d)
            }
            _ => None,
        }
    }

    /// The channels after the layer name.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Distance | Aov::Depth => &["Z"],
            Aov::Position
            | Aov::Normal
            | Aov::GeoNormal
            | Aov::NormalCamera
            | Aov::GeoNormalCamera
            | Aov::SceneFlow(_)
            | Aov::SceneFlowCamera(_) => &["X", "Y", "Z"],
            Aov::Flow(_) => &["X", "Y"],
            Aov::FlowOcclusion(_) => &["M"],
            Aov::Uv => &["U", "V"],
            Aov::Instance | Aov::Label | Aov::Material => &["ID"],
            Aov::Alpha => &["A"],
            // And one per band and response channel, named as the channel
            // (`stderr.S0.550,000000nm`, `stderr.camera.R`), and each extra sensor's
            // (`nikon.stderr.camera.R`): `Sensor::stderr_names`.
            Aov::Stderr => &["Y"],
            // And one per band (`albedo.S0.550,000000nm`), and each extra sensor's bands
            // (`hsi.albedo.S0.550,000000nm`): `Sensor::albedo_names`.
            Aov::Albedo => &["R", "G", "B"],
            Aov::Spp => &["N"],
        }
    }

    /// Integer (32-bit unsigned) channels.
    pub fn is_id(self) -> bool {
        matches!(self, Aov::Instance | Aov::Label | Aov::Material | Aov::Spp)
    }

    /// What it means, for the sidecar.
    pub fn description(self) -> &'static str {
        match self {
            Aov::Distance => "distance from the camera centre to the surface along the pixel-centre ray (scene units; +inf: none)",
            Aov::Depth => "z of the surface along the optical axis, OpenCV camera frame (scene units; +inf: none)",
            Aov::Position => "world position of the surface (scene units; 0: none)",
            Aov::Normal => "unit shading normal, world frame (0: none)",
            Aov::GeoNormal => "unit geometric normal, world frame (0: none)",
            Aov::NormalCamera => "unit shading normal, OpenCV camera frame: x right, y down, z forward (0: none)",
            Aov::GeoNormalCamera => "unit geometric normal, OpenCV camera frame (0: none)",
            Aov::Uv => "surface texture coordinates (0: none)",
            Aov::Instance => "the shape's `id`, else 1 + its index in `shapes` (objects[].instance_id; 0: none)",
            Aov::Label => "id of the shape's label (labels; 0: none or unlabelled)",
            Aov::Material => "1 + index of the shape's material (materials; 0: none)",
            Aov::Alpha => "fraction of the pixel's camera samples that hit a surface (filtered like radiance)",
            Aov::Stderr => "standard error of the pixel's Y, each band (stderr.S0.<λ>nm), response channel and camera.R/G/B, for every sensor (an extra sensor's: <name>.stderr.*), from the spread of its camera samples' own values of that channel: sqrt(sample variance / spp); the RGB spaces and corrected.* have none",
            Aov::Spp => "camera samples the pixel's estimate averaged (sampler.spp; adaptive sampling: the pixel's own count, its pilot included)",
            Aov::Flow(d) => match d {
                Dir::Forward => "optical flow to the frame 1/fps later, pixels, OpenCV image axes (x right, y down): the surface point seen through this pixel's centre is seen there at centre + flow (0: none)",
                Dir::Backward => "optical flow to the frame 1/fps earlier, pixels, OpenCV image axes (x right, y down): the surface point seen through this pixel's centre was seen there at centre + flow (0: none)",
            },
            Aov::FlowOcclusion(_) => "1 where the pixel's surface point is hidden at the flow's other frame, leaves its image, or there is no surface; 0 where it is seen there",
            Aov::SceneFlow(_) => "displacement of the pixel's surface point to the flow's other frame, world frame: p(t ± 1/fps) − p(t) (scene units; 0: none)",
            Aov::SceneFlowCamera(_) => "displacement of the pixel's surface point in OpenCV camera frames, each time's own camera: (R'·p' + t') − (R·p + t) (scene units; 0: none)",
            Aov::Albedo => "diffuse reflectance of the material at the pixel-centre hit (textures at its uv): R/G/B linear sRGB under D65 (constant rho gives R=G=B=rho), and each band's mean (albedo.S0.<λ>nm; an extra sensor's bands: <name>.albedo.S0.<λ>nm); conductors and dielectrics 0; 0: none",
        }
    }

    pub fn parse(name: &str) -> Option<Aov> {
        Aov::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Every valid name, for error messages.
    pub fn names() -> String {
        Aov::ALL.map(|a| a.name()).join(", ")
    }
}

/// A 32-bit unsigned channel (ids).
#[derive(Clone, Debug, PartialEq)]
pub struct UintChannel {
    pub name: String,
    pub data: Vec<u32>,
}
