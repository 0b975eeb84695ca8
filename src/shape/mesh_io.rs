//! Reading meshes from OBJ (tobj) and PLY (ply-rs-bw) files. Errors are plain messages; the
//! scene loader adds the scene file and field they belong to.

use super::mesh::Mesh;
use glam::{Vec2, Vec3};
use ply_rs_bw::ply::{DefaultElement, Property};
use std::path::Path;

/// Loads an OBJ or PLY file by its extension.
pub fn load(path: &Path) -> Result<Mesh, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !path.exists() {
        return Err(format!("mesh file `{}` does not exist", path.display()));
    }
    let mesh = match ext.as_deref() {
        Some("obj") => load_obj(path)?,
        Some("ply") => load_ply(path)?,
        _ => {
            return Err(format!(
                "`{}` is neither .obj nor .ply (the mesh formats prism reads)",
                path.display()
            ))
        }
    };
    mesh.validate()
        .map_err(|m| format!("`{}`: {m}", path.display()))?;
    Ok(mesh)
}

fn load_obj(path: &Path) -> Result<Mesh, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj(path, &opts).map_err(|e| format!("`{}`: OBJ {e}", path.display()))?;
    let mut mesh = Mesh::default();
    let all_normals = models.iter().all(|m| !m.mesh.normals.is_empty());
    let all_uvs = models.iter().all(|m| !m.mesh.texcoords.is_empty());
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if all_normals {
            mesh.normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        }
        if all_uvs {
            // OBJ puts the texture origin at the bottom left; prism's texture space (Mitsuba's)
            // has it at the top left, so v is flipped, as Mitsuba's OBJ loader does by default.
            mesh.uvs.extend(
                m.texcoords
                    .chunks_exact(2)
                    .map(|t| Vec2::new(t[0], 1.0 - t[1])),
            );
        }
        mesh.indices.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    Ok(mesh)
}

fn scalar(p: &Property) -> Option<f32> {
    Some(match *p {
        Property::Char(v) => v as f32,
        Property::UChar(v) => v as f32,
        Property::Short(v) => v as f32,
        Property::UShort(v) => v as f32,
        Property::Int(v) => v as f32,
        Property::UInt(v) => v as f32,
        Property::Float(v) => v,
        Property::Double(v) => v as f32,
        _ => return None,
    })
}

fn index_list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

fn load_ply(path: &Path) -> Result<Mesh, String> {
    let name = path.display();
    let file = std::fs::File::open(path).map_err(|e| format!("`{name}`: {e}"))?;
    let mut reader = std::io::BufReader::new(file);
    let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|e| format!("`{name}`: PLY {e}"))?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or(format!("`{name}` has no `vertex` element"))?;
    let faces = ply
        .payload
        .get("face")
        .ok_or(format!("`{name}` has no `face` element"))?;
    let get =
        |v: &DefaultElement, keys: &[&str]| keys.iter().find_map(|k| v.get(*k).and_then(scalar));
    let mut mesh = Mesh::default();
    let has_normals = vertices.first().is_some_and(|v| get(v, &["nx"]).is_some());
    let has_uvs = vertices
        .first()
        .is_some_and(|v| get(v, &["u", "s", "texture_u"]).is_some());
    for (i, v) in vertices.iter().enumerate() {
        let coord = |k: &str| get(v, &[k]).ok_or(format!("`{name}`: vertex {i} lacks `{k}`"));
        mesh.positions
            .push(Vec3::new(coord("x")?, coord("y")?, coord("z")?));
        if has_normals {
            mesh.normals
                .push(Vec3::new(coord("nx")?, coord("ny")?, coord("nz")?));
        }
        if has_uvs {
            let u = get(v, &["u", "s", "texture_u"]).unwrap_or(0.0);
            let w = get(v, &["v", "t", "texture_v"]).unwrap_or(0.0);
            mesh.uvs.push(Vec2::new(u, w));
        }
    }
    for (f, face) in faces.iter().enumerate() {
        let idx = ["vertex_indices", "vertex_index"]
            .iter()
            .find_map(|k| face.get(*k).and_then(index_list))
            .ok_or(format!("`{name}`: face {f} has no `vertex_indices` list"))?;
        if idx.len() < 3 {
            return Err(format!(
                "`{name}`: face {f} has {} vertices (at least 3 needed)",
                idx.len()
            ));
        }
        if let Some(&bad) = idx
            .iter()
            .find(|&&i| i < 0 || i as usize >= mesh.positions.len())
        {
            return Err(format!(
                "`{name}`: face {f} uses vertex {bad}, but the file has {} vertices",
                mesh.positions.len()
            ));
        }
        // Polygons become triangle fans.
        for k in 1..idx.len() - 1 {
            mesh.indices
                .push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
