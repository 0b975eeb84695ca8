//! Normal-mapped glTF meshes under several nodes are instanced (`shape::instance`): the mesh and
//! its tangents are stored once, in mesh space, and each hit maps its triangle's tangents by the
//! instance's transform (by the linear part, the bitangent sign negated where the node mirrors).
//! Proof: shading normals against closed forms on a flat quad under translated, mirrored,
//! rotated and skewed nodes; and a curved normal-mapped mesh under four nodes (mirrored,
//! rotated and non-uniformly scaled among them) renders as its flattened twin (`flatten: true`,
//! each use copied into world space), normal AOV, ids and image alike, with the file's tangents
//! and with MikkTSpace's.
mod common;
mod scratch;

use glam::{Mat3, Quat, Vec2, Vec3, Vec4};
use prism::film::Film;
use prism::math::portable;
use prism::shape::Shape;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("instnm", name)
}

/// Vertex data of one glTF mesh primitive.
struct Prim {
    pos: Vec<Vec3>,
    nrm: Vec<Vec3>,
    uv: Vec<Vec2>,
    tan: Vec<Vec4>,
    idx: Vec<u32>,
}

/// A normal texture of `w` × `h` tangent-space normals, written as PNG.
fn normal_png(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> Vec3) {
    let mut px = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let n = f(x, y).normalize();
            px.extend(
                n.to_array()
                    .map(|c| ((c + 1.0) * 0.5 * 255.0).round() as u8),
            );
        }
    }
    image::RgbImage::from_raw(w, h, px)
        .unwrap()
        .save(path)
        .unwrap();
}

/// A glTF file `name`.gltf in `dir` with buffer `name`.bin: `prims[0]` (material 0, normal
/// texture `normal.png`, LINEAR filtering, REPEAT) and any further ones without a material,
/// each its own mesh; `tangents`: write `prims[0]`'s TANGENT attribute. `nodes`: the node
/// list (JSON), scene roots `roots`.
fn write_gltf(
    dir: &Path,
    name: &str,
    prims: &[Prim],
    tangents: bool,
    nodes: serde_json::Value,
    roots: &[usize],
) -> PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes) = (Vec::new(), Vec::new(), Vec::new());
    // One buffer view and accessor per attribute (f32 `kind`) or index list (u32 scalars).
    let mut add = |bytes: Vec<u8>, mut accessor: serde_json::Value| {
        let off = bin.len();
        bin.extend(bytes);
        views.push(json!({"buffer": 0, "byteOffset": off, "byteLength": bin.len() - off}));
        accessor["bufferView"] = json!(views.len() - 1);
        accessors.push(accessor);
        accessors.len() - 1
    };
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    for (k, p) in prims.iter().enumerate() {
        let n = p.pos.len();
        let lo = p.pos.iter().fold(Vec3::INFINITY, |a, b| a.min(*b));
        let hi = p.pos.iter().fold(Vec3::NEG_INFINITY, |a, b| a.max(*b));
        let f32s = |kind: &str| json!({"componentType": 5126, "count": n, "type": kind});
        let mut pos = f32s("VEC3");
        pos["min"] = json!(lo.to_array());
        pos["max"] = json!(hi.to_array());
        let flat3 = |v: &[Vec3]| floats(&v.iter().flat_map(|x| x.to_array()).collect::<Vec<_>>());
        let mut attrs = json!({"POSITION": add(flat3(&p.pos), pos)});
        if !p.nrm.is_empty() {
            attrs["NORMAL"] = json!(add(flat3(&p.nrm), f32s("VEC3")));
        }
        if !p.uv.is_empty() {
            let uv: Vec<f32> = p.uv.iter().flat_map(|x| x.to_array()).collect();
            attrs["TEXCOORD_0"] = json!(add(floats(&uv), f32s("VEC2")));
        }
        if tangents && k == 0 {
            let t: Vec<f32> = p.tan.iter().flat_map(|x| x.to_array()).collect();
            attrs["TANGENT"] = json!(add(floats(&t), f32s("VEC4")));
        }
        let idx = add(
            p.idx.iter().flat_map(|x| x.to_le_bytes()).collect(),
            json!({"componentType": 5125, "count": p.idx.len(), "type": "SCALAR"}),
        );
        let mut prim = json!({"attributes": attrs, "indices": idx});
        if k == 0 {
            prim["material"] = json!(0);
        }
        meshes.push(json!({"name": format!("mesh{k}"), "primitives": [prim]}));
    }
    std::fs::write(dir.join(format!("{name}.bin")), &bin).unwrap();
    let doc = json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": roots}],
        "nodes": nodes, "meshes": meshes,
        "materials": [{"name": "bumps", "normalTexture": {"index": 0},
                       "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1], "metallicFactor": 0, "roughnessFactor": 0.4}}],
        "textures": [{"source": 0, "sampler": 0}], "images": [{"uri": "normal.png"}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
        "buffers": [{"byteLength": bin.len(), "uri": format!("{name}.bin")}],
        "bufferViews": views, "accessors": accessors,
    });
    let file = dir.join(format!("{name}.gltf"));
    std::fs::write(&file, serde_json::to_string(&doc).unwrap()).unwrap();
    file
}

/// A unit quad in z = 0, normal +z, glTF's uv layout (u along +x, v down the image = along −y),
/// tangent +x (w = 1).
fn quad() -> Prim {
    let c = [[0.0f32, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    Prim {
        pos: c.iter().map(|c| Vec3::new(c[0], c[1], 0.0)).collect(),
        nrm: vec![Vec3::Z; 4],
        uv: c.iter().map(|c| Vec2::new(c[0], 1.0 - c[1])).collect(),
        tan: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        idx: vec![0, 1, 2, 2, 3, 0],
    }
}

/// A bumpy sphere (`nu` × `nv` latitude-longitude grid; u along the longitude, v down from the
/// north pole), with outward normals and tangents along +u (w = 1).
fn bumpy_sphere(nu: u32, nv: u32) -> Prim {
    let f = |th: f32, ph: f32| {
        let r = 1.0 + 0.12 * portable::sin(3.0 * th) * portable::cos(4.0 * ph) * portable::sin(th);
        Vec3::new(
            portable::sin(th) * portable::cos(ph),
            portable::cos(th),
            portable::sin(th) * portable::sin(ph),
        ) * r
    };
    let mut p = Prim {
        pos: vec![],
        nrm: vec![],
        uv: vec![],
        tan: vec![],
        idx: vec![],
    };
    for j in 0..=nv {
        for i in 0..=nu {
            let (th, ph) = (
                std::f32::consts::PI * (0.04 + 0.92 * j as f32 / nv as f32),
                std::f32::consts::TAU * i as f32 / nu as f32,
            );
            let e = 1e-3;
            let (dth, dph) = (f(th + e, ph) - f(th - e, ph), f(th, ph + e) - f(th, ph - e));
            p.pos.push(f(th, ph));
            p.nrm.push(dph.cross(dth).normalize());
            p.uv.push(Vec2::new(i as f32 / nu as f32, j as f32 / nv as f32));
            p.tan.push(dph.normalize().extend(1.0));
        }
    }
    let v = |i: u32, j: u32| j * (nu + 1) + i;
    for j in 0..nv {
        for i in 0..nu {
            let q = [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)];
            p.idx.extend([q[0], q[2], q[1], q[0], q[3], q[2]]);
        }
    }
    p
}

fn trs(t: [f32; 3], r: Quat, s: [f32; 3]) -> serde_json::Value {
    json!({"translation": t, "rotation": r.to_array(), "scale": s})
}

/// The shared mesh of every instance in the scene (asserting that there is one), and the
/// number of instances.
fn shared_mesh(shapes: &[Shape]) -> (Arc<prism::shape::Mesh>, usize) {
    let inst: Vec<_> = shapes
        .iter()
        .filter_map(|s| match s {
            Shape::Instance(i) => Some(i.mesh.clone()),
            _ => None,
        })
        .collect();
    assert!(!inst.is_empty(), "no instances");
    assert!(
        inst.iter().all(|m| Arc::ptr_eq(m, &inst[0])),
        "the instances do not share one mesh"
    );
    (inst[0].clone(), inst.len())
}

/// A normal-mapped quad (one tangent-space normal `m` everywhere) under four nodes, all four
/// instanced: the shading normal a ray down −z meets is, in closed form with tangent t′ =
/// normalize(L·x) (the tangent by the node's linear part L, glTF's convention, as the Khronos
/// sample viewer's vertex shader applies the model matrix to it), normal z, bitangent
/// b′ = L·y direction = ±z × t′:
/// translated: m; mirrored (x ↦ −x; the mirror image of the bump): (−m.x, m.y, m.z); rotated
/// 90° about z: (−m.y, m.x, m.z); skewed (rotated 30° about z, then scaled (2, 0.5, 1)):
/// m.x·t′ + m.y·(z × t′) + m.z·z with t′ = normalize(S·R·x), which the inverse transpose
/// (normalize(S⁻¹·R·x), 60° away) would miss. With the file's TANGENTs and with MikkTSpace's.
/// Tolerance 0.01: the texel is 8-bit.
#[test]
fn instanced_normal_maps_follow_their_node() {
    let m = Vec3::new(0.45, 0.3, 0.0);
    let m = Vec3::new(m.x, m.y, (1.0 - m.length_squared()).sqrt());
    let dir = workdir("quad");
    normal_png(&dir.join("normal.png"), 1, 1, |_, _| m);
    let rot30 = prism::math::rotation::quat(Vec3::Z, 30f32.to_radians());
    let nodes = json!([
        {"name": "moved", "mesh": 0, "translation": [-3.0, 0.0, 0.0]},
        {"name": "mirrored", "mesh": 0, "scale": [-1.0, 1.0, 1.0], "translation": [3.0, 0.0, 0.0]},
        {"name": "turned", "mesh": 0, "rotation": prism::math::rotation::quat(Vec3::Z, 90f32.to_radians()).to_array(), "translation": [0.0, 3.0, 0.0]},
        {"name": "skewer", "scale": [2.0, 0.5, 1.0], "children": [4]},
        {"name": "skewed", "mesh": 0, "rotation": rot30.to_array(), "translation": [0.0, -8.0, 0.0]}
    ]);
    let skew = Mat3::from_diagonal(Vec3::new(2.0, 0.5, 1.0)) * Mat3::from_quat(rot30);
    let t_skew = (skew * Vec3::X).normalize();
    let expect_skew = m.x * t_skew + m.y * Vec3::Z.cross(t_skew) + m.z * Vec3::Z;
    // World points inside each quad, with the normal expected there.
    let cases = [
        ("moved", Vec3::new(-2.6, 0.3, 0.0), m),
        (
            "mirrored",
            Vec3::new(2.4, 0.6, 0.0),
            Vec3::new(-m.x, m.y, m.z),
        ),
        (
            "turned",
            Vec3::new(-0.4, 3.3, 0.0),
            Vec3::new(-m.y, m.x, m.z),
        ),
        (
            "skewed",
            skew * Vec3::new(0.5, 0.5, 0.0) + Vec3::new(0.0, -4.0, 0.0),
            expect_skew,
        ),
    ];
    for tangents in [true, false] {
        let file = write_gltf(
            &dir,
            &format!("q{}", tangents as u8),
            &[quad()],
            tangents,
            nodes.clone(),
            &[0, 1, 2, 3],
        );
        let job = prism::load::load(&file, |c| {
            c.film.width = 16;
            c.film.height = 16;
        })
        .unwrap();
        assert!(job.warnings.is_empty(), "{:?}", job.warnings);
        let s = &job.scene;
        assert_eq!(s.instance_counts(), (4, 1, 2), "four instances of one quad");
        let (mesh, _) = shared_mesh(&s.shapes);
        let nm = mesh
            .normal_map
            .as_ref()
            .expect("the shared mesh keeps its normal map");
        // Mesh-space tangents: the file's (+x, w = 1), or MikkTSpace's along +u: +x too.
        for t in &nm.tangents {
            assert!(
                (*t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-5,
                "tangent {t}"
            );
        }
        for (name, p, want) in cases {
            let ray = prism::ray::Ray {
                o: p + Vec3::Z,
                d: -Vec3::Z,
                t_max: 10.0,
                time: 0.0,
            };
            let si = s
                .intersect(&ray)
                .unwrap_or_else(|| panic!("{name} is not hit at {p}"));
            let shape = s.shape_name[si.shape as usize].as_deref();
            assert_eq!(shape, Some(name), "at {p}");
            let n = si.frame.n;
            assert!(
                (n - want.normalize()).length() < 0.01,
                "{name} (tangents in the file: {tangents}): shading normal {n}, want {want}"
            );
        }
    }
}

fn render(job: &prism::load::Job) -> Film {
    let mut film = prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
    prism::pipeline::add_layers(job, &mut film, None);
    film
}

fn ids(f: &Film, name: &str) -> Vec<u32> {
    f.uint_channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no id channel {name}"))
        .data
        .clone()
}

/// A bumpy sphere (16 × 10 quads, 320 triangles, 187 vertices) with an 8 × 8 normal texture
/// (tilts up to 0.45, bilinear), under four nodes: translated; rotated 20° and mirrored
/// (scale (−0.9, 0.9, 0.9)); rotated 50° about (1, 1, 0) and scaled (1.3, 0.6, 0.9); scaled
/// under a rotated parent; and a floor used once. Instanced, the sphere and its 187 tangents
/// are stored once (flattened: four world-space copies); both count the same triangles. The
/// instanced render against its flattened twin: ids identical at every pixel; shading normals
/// (normal AOV) within 1e-3 per component at every pixel (the instanced ray is intersected in
/// object space, so its barycentrics differ from the world-space test's by ~1e-6, moving the
/// interpolated normal, the tangents and the bilinear texel lookup by ~1e-5; a wrong tangent
/// transform or bitangent sign moves them by the map's tilt, ~0.1–0.5); image means within
/// 0.2% and 97% of pixels within 0.1% (both draw the same random numbers; a last-bit
/// difference may flip a discrete choice), as the other twin tests.
#[test]
fn normal_mapped_gltf_mesh_renders_as_its_flattened_twin() {
    let dir = workdir("twin");
    normal_png(&dir.join("normal.png"), 8, 8, |x, y| {
        let (a, b) = (x as f32 * 0.785 + 1.0, y as f32 * 0.785);
        Vec3::new(0.45 * portable::sin(a), 0.45 * portable::cos(b), 1.0)
    });
    let sphere = bumpy_sphere(16, 10);
    let (verts, tris) = (sphere.pos.len(), sphere.idx.len() / 3);
    assert_eq!((verts, tris), (187, 320));
    let y = 1.5f32;
    let floor = Prim {
        pos: vec![
            Vec3::new(-8.0, -y, -8.0),
            Vec3::new(8.0, -y, -8.0),
            Vec3::new(8.0, -y, 8.0),
            Vec3::new(-8.0, -y, 8.0),
        ],
        nrm: vec![],
        uv: vec![],
        tan: vec![],
        idx: vec![0, 3, 2, 0, 2, 1],
    };
    let axis = Vec3::new(1.0, 1.0, 0.0).normalize();
    let nodes = json!([
        {"name": "plain", "mesh": 0, "translation": [-2.0, 0.0, 1.2]},
        trs([2.0, 0.0, 1.2], prism::math::rotation::quat(Vec3::Z, 20f32.to_radians()), [-0.9, 0.9, 0.9]),
        trs([-2.0, 0.2, -1.8], prism::math::rotation::quat(axis, 50f32.to_radians()), [1.3, 0.6, 0.9]),
        {"name": "parent", "rotation": prism::math::rotation::quat(Vec3::Y, 45f32.to_radians()).to_array(), "translation": [2.0, 0.0, -1.8], "children": [4]},
        {"name": "child", "mesh": 0, "scale": [0.8, 0.8, 0.8]},
        {"name": "floor", "mesh": 1}
    ]);
    let mut nodes = nodes;
    nodes[1]["name"] = json!("mirrored");
    nodes[1]["mesh"] = json!(0);
    nodes[2]["name"] = json!("squashed");
    nodes[2]["mesh"] = json!(0);
    let prims = [sphere, floor];
    for tangents in [true, false] {
        let file = write_gltf(
            &dir,
            &format!("s{}", tangents as u8),
            &prims,
            tangents,
            nodes.clone(),
            &[0, 1, 2, 3, 5],
        );
        let scene = |flatten: bool| {
            format!(
                r#"(camera: (fov: 45, to_world: [LookAt(origin: (0, 4, 8), target: (0, 0, -0.3), up: (0, 1, 0))]),
                   film: (width: 64, height: 48), sampler: (spp: 4, seed: 3), spectral: (wavelengths: 4), flatten: {flatten},
                   shapes: [(shape: Gltf(path: "{}"))],
                   emitters: [Constant(radiance: Named("D65"))],
                   aovs: ["normal", "instance"])"#,
                file.file_name().unwrap().to_str().unwrap()
            )
        };
        let at = dir.join("s.ron");
        let inst = prism::load::load_str(&scene(false), &at).unwrap();
        let flat = prism::load::load_str(&scene(true), &at).unwrap();
        assert!(inst.warnings.is_empty(), "{:?}", inst.warnings);
        let names: Vec<_> = inst.scene.shape_name.iter().flatten().cloned().collect();
        assert_eq!(names, ["plain", "mirrored", "squashed", "child", "floor"]);
        assert_eq!(inst.scene.shape_name, flat.scene.shape_name);

        // Stored once: one shared mesh with one set of mesh-space tangents (the file's as
        // written, when it has them), against four world-space copies flattened.
        assert_eq!(inst.scene.instance_counts(), (4, 1, tris as u64));
        assert_eq!(flat.scene.instance_counts(), (0, 0, 0));
        assert_eq!(inst.scene.primitive_count(), 4 * tris + 2);
        assert_eq!(flat.scene.primitive_count(), 4 * tris + 2);
        let (mesh, uses) = shared_mesh(&inst.scene.shapes);
        assert_eq!((uses, mesh.positions.len()), (4, verts));
        let nm = mesh
            .normal_map
            .as_ref()
            .expect("normal map on the shared mesh");
        assert_eq!(nm.tangents.len(), verts);
        if tangents {
            assert_eq!(
                nm.tangents, prims[0].tan,
                "the file's tangents, in mesh space"
            );
        }
        let copies = |shapes: &[Shape]| {
            shapes
                .iter()
                .map(|s| match s {
                    Shape::Mesh(m) => m.normal_map.as_ref().map_or(0, |n| n.tangents.len()),
                    _ => 0,
                })
                .sum::<usize>()
        };
        assert_eq!(copies(&inst.scene.shapes), 0);
        assert_eq!(copies(&flat.scene.shapes), 4 * verts);
        // The memory estimate's count: the mesh once plus one per instance, against four copies.
        use prism::load::instancing::unique_prims;
        assert_eq!(unique_prims(&inst.scene.shapes), (tris + 4 + 2) as u64);
        assert_eq!(unique_prims(&flat.scene.shapes), (4 * tris + 2) as u64);

        let (fi, ff) = (render(&inst), render(&flat));
        let (ii, if_) = (ids(&fi, "instance.ID"), ids(&ff, "instance.ID"));
        assert_eq!(ii, if_, "instance ids differ");
        let seen: std::collections::BTreeSet<u32> = ii.iter().copied().collect();
        assert!(
            (1..=5).all(|id| seen.contains(&id)),
            "not all in view: {seen:?}"
        );
        let n = ii.len();
        let mut worst = 0f32;
        let tilted = ii.iter().filter(|id| (1..=4).contains(*id)).count();
        for k in 0..n {
            let get = |f: &Film, c: &str| f.channel(&format!("normal.{c}")).unwrap()[k];
            let a = Vec3::new(get(&fi, "X"), get(&fi, "Y"), get(&fi, "Z"));
            let b = Vec3::new(get(&ff, "X"), get(&ff, "Y"), get(&ff, "Z"));
            worst = worst.max((a - b).abs().max_element());
        }
        eprintln!("tangents in the file: {tangents}: worst normal difference {worst:e} over {n} pixels ({tilted} on the spheres)");
        assert!(tilted * 5 > n, "the spheres cover {tilted} of {n} pixels");
        assert!(worst <= 1e-3, "shading normals differ by {worst}");

        common::assert_same_radiance(fi.channel("R").unwrap(), ff.channel("R").unwrap());
    }
}
