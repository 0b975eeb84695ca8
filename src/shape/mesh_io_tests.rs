//! Tests of the OBJ and PLY readers (`shape::mesh_io`).

use super::*;
use glam::Vec2;

fn temp(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("prism-meshio-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn reads_obj_and_ply_quads() {
    let obj = temp("q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    let m = load(&obj).unwrap();
    assert_eq!(m.indices.len(), 2);
    let ply = temp(
        "q.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
    );
    let m = load(&ply).unwrap();
    assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn obj_texture_v_is_flipped() {
    let obj = temp(
        "uv.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0.25\nvt 0 1\nf 1/1 2/2 3/3\n",
    );
    let m = load(&obj).unwrap();
    assert_eq!(
        m.uvs,
        vec![
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 0.75),
            Vec2::new(0.0, 0.0)
        ]
    );
}

#[test]
fn reports_bad_files() {
    assert!(load(Path::new("/nonexistent/x.obj"))
        .unwrap_err()
        .contains("does not exist"));
    let bad = temp("bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 1 2\n");
    assert!(load(&bad).unwrap_err().contains("uses vertex"));
    let txt = temp("m.stl", "solid");
    assert!(load(&txt).unwrap_err().contains("neither"));
}
