//! Instancing (a mesh used by several shapes or glTF nodes is stored once, `accel::instances`):
//! an instanced scene renders as its flattened twin (`flatten: true`, every use copied into
//! world space, the path single-use meshes always take), AOVs included, with translated,
//! rotated, non-uniformly scaled, mirrored and flipped instances; a glTF mesh under several
//! nodes is instanced with the file's counts; 1,000 instances of a 100k-triangle mesh take less
//! than twice the peak memory of one; the memory estimate counts unique geometry.

mod common;
mod scratch;

use prism::film::Film;
use prism::integrator;
use prism::math::portable;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("inst", name)
}

/// A bumpy sphere as OBJ (a `nu` × `nv` latitude-longitude grid), with vertex normals and uvs
/// when `smooth`; the bumps make neighbouring triangles face different ways.
fn bumpy_obj(nu: usize, nv: usize, smooth: bool) -> String {
    let mut s = String::new();
    let f = |th: f32, ph: f32| {
        let r = 1.0 + 0.15 * portable::sin(3.0 * th) * portable::cos(4.0 * ph) * portable::sin(th);
        glam::Vec3::new(
            portable::sin(th) * portable::cos(ph),
            portable::cos(th),
            portable::sin(th) * portable::sin(ph),
        ) * r
    };
    for j in 0..=nv {
        for i in 0..=nu {
            let (th, ph) = (
                std::f32::consts::PI * (0.05 + 0.9 * j as f32 / nv as f32),
                std::f32::consts::TAU * i as f32 / nu as f32,
            );
            let p = f(th, ph);
            writeln!(s, "v {} {} {}", p.x, p.y, p.z).unwrap();
            if smooth {
                let e = 1e-3;
                let n = (f(th + e, ph) - f(th - e, ph))
                    .cross(f(th, ph + e) - f(th, ph - e))
                    .normalize();
                writeln!(s, "vn {} {} {}", -n.x, -n.y, -n.z).unwrap();
                writeln!(s, "vt {} {}", i as f32 / nu as f32, j as f32 / nv as f32).unwrap();
            }
        }
    }
    let v = |i: usize, j: usize| j * (nu + 1) + i + 1;
    for j in 0..nv {
        for i in 0..nu {
            let q = [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)];
            for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                if smooth {
                    writeln!(s, "f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}", t[0], t[1], t[2]).unwrap();
                } else {
                    writeln!(s, "f {} {} {}", t[0], t[1], t[2]).unwrap();
                }
            }
        }
    }
    s
}

/// Seven uses of two meshes (one smooth with uvs, one flat without): translated, rotated,
/// scaled non-uniformly, mirrored (negative determinant), flipped, and both at once.
fn twin_scene(flatten: bool) -> String {
    format!(
        r#"(
    camera: (fov: 40, to_world: [LookAt(origin: (0, 2.5, 9), target: (0, 0.6, 0), up: (0, 1, 0))]),
    film: (width: 64, height: 48),
    sampler: (spp: 8, seed: 5),
    spectral: (wavelengths: 4),
    flatten: {flatten},
    materials: {{
        "white": Diffuse(reflectance: Rgb(0.7, 0.7, 0.7)),
        "metal": RoughConductor(material: "Cu", distribution: Ggx, alpha: 0.2),
        "red": Diffuse(reflectance: Rgb(0.8, 0.2, 0.1)),
    }},
    shapes: [
        (shape: Rectangle, material: "white", to_world: [Scale((10, 10, 1)), Rotate(axis: (1, 0, 0), angle: -90)]),
        (shape: Rectangle, emitter: (radiance: Scaled(6, Named("D65"))),
         to_world: [Scale((1.5, 1.5, 1)), Rotate(axis: (1, 0, 0), angle: 90), Translate((1, 5, 2))]),
        (shape: Mesh(path: "ball.obj"), material: "metal", name: "b0", to_world: [Scale((0.8, 0.8, 0.8)), Translate((-2.6, 1, 0))]),
        (shape: Mesh(path: "ball.obj"), material: "red", name: "b1", to_world: [Scale((0.8, 0.8, 0.8)), Rotate(axis: (1, 1, 0), angle: 50), Translate((-0.9, 1, 0))]),
        (shape: Mesh(path: "ball.obj"), material: "metal", name: "b2", to_world: [Scale((1.1, 0.5, 0.7)), Rotate(axis: (0, 1, 1), angle: 30), Translate((0.9, 0.6, 0))]),
        (shape: Mesh(path: "ball.obj"), material: "red", name: "b3", label: "mirrored", to_world: [Scale((-0.8, 0.8, 0.8)), Rotate(axis: (0, 0, 1), angle: 20), Translate((2.6, 1, 0))]),
        (shape: Mesh(path: "./ball.obj"), material: "white", name: "b4", flip_normals: true, to_world: [Translate((0, 1, -2.5))]),
        (shape: Mesh(path: "rock.obj"), material: "metal", name: "r0", to_world: [Scale((0.5, 0.3, 0.5)), Translate((-1.5, 0.3, 2))]),
        (shape: Mesh(path: "rock.obj"), material: "red", name: "r1", flip_normals: true, label: "mirrored",
         to_world: [Scale((0.4, -0.6, 0.4)), Rotate(axis: (1, 0, 0), angle: 15), Translate((1.5, 0.4, 2))]),
    ],
    emitters: [Constant(radiance: Scaled(0.3, Named("D65")))],
    aovs: ["depth", "position", "normal", "geo_normal", "instance", "label"],
)"#
    )
}

fn render(job: &prism::load::Job) -> Film {
    let mut film = integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
    prism::pipeline::add_layers(job, &mut film, None);
    film
}

fn ch<'a>(f: &'a Film, name: &str) -> &'a [f32] {
    f.channel(name)
        .unwrap_or_else(|| panic!("no channel {name}"))
}

fn ids<'a>(f: &'a Film, name: &str) -> &'a [u32] {
    &f.uint_channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no id channel {name}"))
        .data
}

/// The instanced scene against its flattened twin. Not bit-identical, by construction: the
/// instanced ray is intersected in object space (its origin and direction rounded by the
/// inverse transform), so t and the barycentrics differ from the world-space test's in the
/// last bits; the surface data are then computed from the same world-space vertex values
/// (`shape::instance`). Tolerances: ids may differ only where a pixel-centre ray grazes a
/// silhouette (at most 0.5% of pixels; 0 were seen); depth within 1e-4 relative (the rounding
/// of a 3×4 transform, ~1e-6, with margin), positions within 1e-4 of the scene's scale,
/// normals within 1e-3 (interpolation weights differing by ~1e-6). Colour: both renders draw
/// the same random numbers per pixel, so a path changes only where a last-bit difference
/// flips a discrete choice (a shadow ray grazing an edge); the image means must agree within
/// 0.2% and 97% of pixels within 0.1% (a wrong normal transform, winding or id breaks both by
/// orders of magnitude: mirrored instances shade their inside, a swapped normal darkens).
#[test]
fn instanced_scene_renders_as_its_flattened_twin() {
    let dir = workdir("twin");
    std::fs::write(dir.join("ball.obj"), bumpy_obj(24, 16, true)).unwrap();
    std::fs::write(dir.join("rock.obj"), bumpy_obj(9, 6, false)).unwrap();
    let file = dir.join("twin.ron");
    let inst = prism::load::load_str(&twin_scene(false), &file).unwrap();
    let flat = prism::load::load_str(&twin_scene(true), &file).unwrap();
    let (ball, rock) = (24 * 16 * 2, 9 * 6 * 2);
    assert_eq!(
        inst.scene.instance_counts(),
        (7, 2, (ball + rock) as u64),
        "seven instances of two meshes (\"ball.obj\" and \"./ball.obj\" are one file)"
    );
    assert_eq!(flat.scene.instance_counts(), (0, 0, 0));
    assert_eq!(inst.scene.primitive_count(), flat.scene.primitive_count());
    assert_eq!(inst.scene.primitive_count(), 4 + 5 * ball + 2 * rock);
    let (lo_i, hi_i) = inst.scene.bounds();
    let (lo_f, hi_f) = flat.scene.bounds();
    assert!(
        (lo_i - lo_f).abs().max_element() < 1e-5 && (hi_i - hi_f).abs().max_element() < 1e-5,
        "bounds {lo_i}..{hi_i} instanced, {lo_f}..{hi_f} flattened"
    );
    // The sidecar's objects: same names, ids and bounds.
    for (a, b) in inst.objects.list.iter().zip(&flat.objects.list) {
        assert_eq!(
            (&a.name, a.instance_id, a.label_id),
            (&b.name, b.instance_id, b.label_id)
        );
        assert!(
            (a.bounds.0 - b.bounds.0).abs().max_element() < 1e-5,
            "{}",
            a.name
        );
        assert!(
            (a.bounds.1 - b.bounds.1).abs().max_element() < 1e-5,
            "{}",
            a.name
        );
    }

    let (fi, ff) = (render(&inst), render(&flat));
    let n = 64 * 48;
    let (ii, if_) = (ids(&fi, "instance.ID"), ids(&ff, "instance.ID"));
    let differ = ii.iter().zip(if_).filter(|(a, b)| a != b).count();
    assert!(
        differ * 200 <= n,
        "{differ} of {n} pixels see another instance"
    );
    let seen: std::collections::BTreeSet<u32> = ii.iter().copied().collect();
    for id in 3..=9 {
        assert!(seen.contains(&id), "instance {id} is not in view: {seen:?}");
    }
    assert_eq!(ids(&fi, "label.ID"), ids(&ff, "label.ID"));
    let same: Vec<usize> = (0..n).filter(|&k| ii[k] == if_[k] && ii[k] != 0).collect();
    let (di, df) = (ch(&fi, "depth.Z"), ch(&ff, "depth.Z"));
    let mut worst = [0f32; 3];
    for &k in &same {
        worst[0] = worst[0].max((di[k] - df[k]).abs() / df[k]);
        for c in ["X", "Y", "Z"] {
            let (a, b) = (
                ch(&fi, &format!("position.{c}")),
                ch(&ff, &format!("position.{c}")),
            );
            worst[1] = worst[1].max((a[k] - b[k]).abs());
            for layer in ["normal", "geo_normal"] {
                let (a, b) = (
                    ch(&fi, &format!("{layer}.{c}")),
                    ch(&ff, &format!("{layer}.{c}")),
                );
                worst[2] = worst[2].max((a[k] - b[k]).abs());
            }
        }
    }
    eprintln!(
        "ids differ at {differ} of {n} pixels; worst depth {:e} (relative), position {:e}, normal {:e}",
        worst[0], worst[1], worst[2]
    );
    assert!(
        worst[0] < 1e-4 && worst[1] < 1e-4 && worst[2] < 1e-3,
        "{worst:?}"
    );

    common::assert_same_radiance(ch(&fi, "R"), ch(&ff, "R"));
}

/// A glTF file with one mesh under four nodes (translated, rotated about a parent, mirrored,
/// scaled) and another under one: the first is instanced (four instances, one unique mesh),
/// the second copied; names come from the nodes; counts match the file; and it renders as its
/// flattened twin (same tolerances as above).
#[test]
fn gltf_mesh_under_several_nodes_is_instanced() {
    let dir = workdir("gltf");
    // A unit tetrahedron (4 triangles) and a quad (2 triangles), little-endian f32 / u16.
    let pos: [[f32; 3]; 8] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-3.0, 0.0, -3.0],
        [3.0, 0.0, -3.0],
        [3.0, 0.0, 3.0],
        [-3.0, 0.0, 3.0],
    ];
    let idx: [u16; 18] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 3, 2, 0, 2, 1];
    let mut bin = Vec::new();
    pos.iter()
        .flatten()
        .for_each(|v| bin.extend(v.to_le_bytes()));
    idx.iter().for_each(|v| bin.extend(v.to_le_bytes()));
    std::fs::write(dir.join("m.bin"), &bin).unwrap();
    let gltf = r#"{"asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0, 1, 2, 3, 5]}],
      "nodes": [
        {"name": "t0", "mesh": 0, "translation": [-2, 0, 0]},
        {"name": "parent", "rotation": [0, 0.3826834, 0, 0.9238795], "translation": [0, 0.5, 0], "children": [4]},
        {"name": "mirror", "mesh": 0, "scale": [-1, 1, 1], "translation": [2, 0, 0]},
        {"name": "squash", "mesh": 0, "scale": [1.5, 0.5, 1], "translation": [0, 0, 1.5]},
        {"name": "child", "mesh": 0, "translation": [0, 0, -1.5]},
        {"name": "floor", "mesh": 1, "translation": [0, -0.01, 0]}
      ],
      "meshes": [{"name": "tet", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
                 {"name": "quad", "primitives": [{"attributes": {"POSITION": 2}, "indices": 3}]}],
      "buffers": [{"byteLength": 132, "uri": "m.bin"}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 96, "byteLength": 24},
                      {"buffer": 0, "byteOffset": 48, "byteLength": 48}, {"buffer": 0, "byteOffset": 120, "byteLength": 12}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]},
        {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-3, 0, -3], "max": [3, 0, 3]},
        {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
      ]}"#;
    std::fs::write(dir.join("m.gltf"), gltf).unwrap();
    let scene = |flatten: bool| {
        format!(
            r#"(camera: (fov: 45, to_world: [LookAt(origin: (1, 4, 6), target: (0, 0.3, 0), up: (0, 1, 0))]),
               film: (width: 48, height: 32), sampler: (spp: 8), spectral: (wavelengths: 4), flatten: {flatten},
               shapes: [(shape: Gltf(path: "m.gltf"))],
               emitters: [Constant(radiance: Named("D65"))],
               aovs: ["depth", "normal", "instance"])"#
        )
    };
    let file = dir.join("s.ron");
    let inst = prism::load::load_str(&scene(false), &file).unwrap();
    let flat = prism::load::load_str(&scene(true), &file).unwrap();
    assert_eq!(inst.scene.instance_counts(), (4, 1, 4));
    assert_eq!(flat.scene.instance_counts(), (0, 0, 0));
    assert_eq!(inst.scene.primitive_count(), 4 * 4 + 2);
    assert_eq!(flat.scene.primitive_count(), 4 * 4 + 2);
    let names: Vec<_> = inst.scene.shape_name.iter().flatten().cloned().collect();
    assert_eq!(names, ["t0", "child", "mirror", "squash", "floor"]);
    assert_eq!(inst.scene.shape_name, flat.scene.shape_name);
    let (fi, ff) = (render(&inst), render(&flat));
    let (ii, if_) = (ids(&fi, "instance.ID"), ids(&ff, "instance.ID"));
    let n = ii.len();
    let differ = ii.iter().zip(if_).filter(|(a, b)| a != b).count();
    assert!(
        differ * 200 <= n,
        "{differ} of {n} pixels see another instance"
    );
    let seen: std::collections::BTreeSet<u32> = ii.iter().copied().collect();
    assert!((1..=5).all(|id| seen.contains(&id)), "{seen:?}");
    for k in (0..n).filter(|&k| ii[k] == if_[k] && ii[k] != 0) {
        let (a, b) = (ch(&fi, "depth.Z")[k], ch(&ff, "depth.Z")[k]);
        assert!((a - b).abs() <= 1e-4 * b, "depth {a} vs {b}");
        for c in ["X", "Y", "Z"] {
            let (a, b) = (
                ch(&fi, &format!("normal.{c}"))[k],
                ch(&ff, &format!("normal.{c}"))[k],
            );
            assert!((a - b).abs() <= 1e-3, "normal.{c} {a} vs {b} at {k}");
        }
    }
    common::assert_same_radiance(ch(&fi, "R"), ch(&ff, "R"));
}

/// A bumpy height field of 224 × 224 quads (100,352 triangles) as binary PLY.
fn write_grid_ply(path: &Path) -> usize {
    let n = 224usize;
    let mut body = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            let y = 0.05 * portable::sin(37.0 * x) * portable::cos(29.0 * z);
            for v in [x, y, z] {
                body.extend(v.to_le_bytes());
            }
        }
    }
    let v = |i: usize, j: usize| (j * (n + 1) + i) as i32;
    for j in 0..n {
        for i in 0..n {
            for t in [
                [v(i, j), v(i, j + 1), v(i + 1, j + 1)],
                [v(i, j), v(i + 1, j + 1), v(i + 1, j)],
            ] {
                body.push(3);
                t.iter().for_each(|k| body.extend(k.to_le_bytes()));
            }
        }
    }
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        (n + 1) * (n + 1),
        2 * n * n
    );
    let mut bytes = header.into_bytes();
    bytes.extend(body);
    std::fs::write(path, bytes).unwrap();
    2 * n * n
}

fn grid_scene(count: usize, flatten: bool) -> String {
    let mut shapes = String::new();
    for k in 0..count {
        let (x, y, z) = ((k % 10) as f32, ((k / 10) % 10) as f32, (k / 100) as f32);
        writeln!(
            shapes,
            "(shape: Mesh(path: \"grid.ply\"), to_world: [Rotate(axis: (0, 1, 0), angle: {}), Translate(({x}, {y}, {z}))]),",
            k * 37 % 360
        )
        .unwrap();
    }
    format!(
        r#"(camera: (fov: 60, to_world: [LookAt(origin: (4.5, 4.5, -12), target: (4.5, 4.5, 4.5), up: (0, 1, 0))]),
           film: (width: 16, height: 16), sampler: (spp: 1), flatten: {flatten},
           shapes: [{shapes}], emitters: [Constant(radiance: Named("D65"))])"#
    )
}

/// 1,000 instances of a 100k-triangle mesh against one use of it (which takes the flattened
/// path): peak resident memory (wait4's ru_maxrss of the `prism` process, 16×16 film, 1 spp)
/// must stay under twice the single use's. Flattened, the 1,000 would be about 100M triangles
/// (~35 GB of BVH by resources.rs). The memory estimate counts the unique geometry: 40 uses
/// flattened (4M triangles, estimated 1.4 GB) are refused under `--max-memory 400MiB`, and the
/// same 40 instanced render.
#[test]
fn thousand_instances_cost_less_than_twice_one() {
    let dir = workdir("memory");
    assert_eq!(write_grid_ply(&dir.join("grid.ply")), 100_352);
    let write = |name: &str, text: String| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let one = write("one.ron", grid_scene(1, false));
    let many = write("many.ron", grid_scene(1000, false));
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (rss_one, rc) = common::peak_rss(&["render", &one, "-o", &out("one.exr"), "-q"]);
    assert_eq!(rc, 0);
    let (rss_many, rc) = common::peak_rss(&["render", &many, "-o", &out("many.exr"), "-q"]);
    assert_eq!(rc, 0);
    let mib = |b: u64| b as f64 / (1 << 20) as f64;
    eprintln!(
        "peak RSS: one use {:.1} MiB, 1000 instances {:.1} MiB ({:.2}×)",
        mib(rss_one),
        mib(rss_many),
        rss_many as f64 / rss_one as f64
    );
    assert!(
        rss_many < 2 * rss_one,
        "1000 instances peaked at {:.1} MiB, one use at {:.1} MiB",
        mib(rss_many),
        mib(rss_one)
    );

    let forty = write("forty.ron", grid_scene(40, false));
    let forty_flat = write("forty_flat.ron", grid_scene(40, true));
    let run = |scene: &str| {
        Command::new(env!("CARGO_BIN_EXE_prism"))
            .args(["render", scene, "-o", &format!("{scene}.exr"), "-q"])
            .args(["--max-memory", "400MiB"])
            .output()
            .unwrap()
    };
    let r = run(&forty_flat);
    assert_eq!(
        r.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("4014080 primitives"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let r = run(&forty);
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
}
