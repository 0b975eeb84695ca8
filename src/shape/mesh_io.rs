//! Reading meshes from OBJ (tobj) and PLY (ply-rs-bw) files. Errors are plain messages; the
//! scene loader adds the scene file and field they belong to.

use super::mesh::Mesh;
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};
use std::path::Path;

/// Loads an OBJ or PLY file by its extension.
pub fn load(path: &Path) -> Result<Mesh, String> {
    crate::scene::inputs::record(path);
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
    let file = crate::config::input_file::open(path, crate::config::input_file::Kind::Mesh)?;
    // prism takes materials from the scene, so `mtllib` files are not opened at all.
    let (models, _materials) =
        tobj::load_obj_buf(&mut std::io::BufReader::new(file), &opts, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| match obj_error_line(path, &e) {
            Some((n, line)) => format!("`{}` line {n} (`{line}`): OBJ {e}", path.display()),
            None => format!("`{}`: OBJ {e}", path.display()),
        })?;
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

/// The line (1-based, and its text) an OBJ error of tobj's is about, which tobj does not say:
/// found by a plain scan, run only once tobj has failed.
fn obj_error_line(path: &Path, e: &tobj::LoadError) -> Option<(usize, String)> {
    use tobj::LoadError as E;
    let text = String::from_utf8_lossy(&std::fs::read(path).ok()?).into_owned();
    let floats =
        |w: &[&str], n: usize| w.len() >= n && w[..n].iter().all(|s| s.parse::<f32>().is_ok());
    // Count of v, vt, vn so far; an index k refers to 1..=count, or count + k + 1 if negative.
    let mut count = [0i64; 3];
    for (i, line) in text.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let (key, rest) = match words.split_first() {
            Some((k, r)) => (*k, r),
            None => continue,
        };
        let index_ok = |slot: usize| {
            rest.iter().all(|c| match c.split('/').nth(slot) {
                None | Some("") => true,
                Some(s) => s.parse::<i64>().is_ok_and(|k| {
                    let k = if k < 0 { count[slot] + k + 1 } else { k };
                    (1..=count[slot]).contains(&k)
                }),
            })
        };
        let bad = match (key, e) {
            ("v", E::PositionParseError) => !floats(rest, 3),
            ("vt", E::TexcoordParseError) => !floats(rest, 1),
            ("vn", E::NormalParseError) => !floats(rest, 3),
            ("f", E::FaceParseError) => {
                rest.len() < 3
                    || rest.iter().any(|c| {
                        c.split('/')
                            .any(|s| !s.is_empty() && s.parse::<i64>().is_err())
                    })
            }
            ("f", E::FaceVertexOutOfBounds) => !index_ok(0),
            ("f", E::FaceTexCoordOutOfBounds) => !index_ok(1),
            ("f", E::FaceNormalOutOfBounds) => !index_ok(2),
            _ => false,
        };
        if bad {
            return Some((i + 1, line.trim().chars().take(80).collect()));
        }
        match key {
            "v" => count[0] += 1,
            "vt" => count[1] += 1,
            "vn" => count[2] += 1,
            _ => {}
        }
    }
    None
}

/// One PLY vertex as prism keeps it. Reading into this (rather than ply-rs-bw's default
/// element, a map from property name to value per vertex) keeps a million-vertex file at a few
/// tens of bytes per vertex while it loads.
struct PlyVertex {
    /// x, y, z, nx, ny, nz, u, v.
    c: [f32; 8],
    /// Bit i set where `c[i]` was in the file.
    set: u8,
}

impl PlyVertex {
    fn slot(name: &str) -> Option<usize> {
        Some(match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "nx" => 3,
            "ny" => 4,
            "nz" => 5,
            "u" | "s" | "texture_u" => 6,
            "v" | "t" | "texture_v" => 7,
            _ => return None,
        })
    }

    fn put(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        match Self::slot(name) {
            Some(i) => {
                self.c[i] = value;
                self.set |= 1 << i;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self {
            c: [0.0; 8],
            set: 0,
        }
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.put(name, value)
    }
    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        match p.to_f32_lossy() {
            Some(v) => self.put(name, v),
            None => PropertyAccessResult::Ignored,
        }
    }
}

/// One PLY face: its vertex indices, inline for triangles and quads.
enum PlyFace {
    Missing,
    Small { n: u8, v: [i64; 4] },
    Large(Vec<i64>),
}

impl PlyFace {
    fn indices(&self) -> Option<&[i64]> {
        match self {
            PlyFace::Missing => None,
            PlyFace::Small { n, v } => Some(&v[..*n as usize]),
            PlyFace::Large(v) => Some(v),
        }
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace::Missing
    }
    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        if name != "vertex_indices" && name != "vertex_index" {
            return PropertyAccessResult::Ignored;
        }
        let list: Vec<i64> = match p {
            Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
            Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
            Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
            Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
            Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
            Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
            _ => return PropertyAccessResult::UnsupportedType,
        };
        *self = if list.len() <= 4 {
            let mut v = [0; 4];
            v[..list.len()].copy_from_slice(&list);
            PlyFace::Small {
                n: list.len() as u8,
                v,
            }
        } else {
            PlyFace::Large(list)
        };
        PropertyAccessResult::Set
    }
}

/// Any other element (skipped).
struct PlyOther;

impl PropertyAccess for PlyOther {
    fn new() -> Self {
        PlyOther
    }
}

/// True if anything but whitespace (ASCII) or anything at all (binary) follows the elements.
fn has_trailing_data(reader: &mut Reader<impl std::io::BufRead>, ascii: bool) -> bool {
    let r = reader.get_mut();
    loop {
        let buf = match r.fill_buf() {
            Ok([]) | Err(_) => return false,
            Ok(b) => b,
        };
        if !ascii || buf.iter().any(|b| !b.is_ascii_whitespace()) {
            return true;
        }
        let n = buf.len();
        r.consume(n);
    }
}

fn load_ply(path: &Path) -> Result<Mesh, String> {
    let name = path.display();
    let file = crate::config::input_file::open(path, crate::config::input_file::Kind::Mesh)?;
    let mut reader = Reader::new(std::io::BufReader::new(file));
    let header = Parser::<PlyOther>::new()
        .read_header(&mut reader)
        .map_err(|e| format!("`{name}`: PLY {e}"))?;
    let (mut vertices, mut faces) = (None, None);
    for element in header.elements.values() {
        let err = |e: ply_rs_bw::parser::ParseError| {
            let e = e.to_string();
            if e.contains("Unexpected end of file") {
                // The header promises more elements than the data holds.
                format!(
                    "`{name}`: the header declares {} `{}` elements, but the file ends before the last of them",
                    element.count, element.name
                )
            } else {
                // ply-rs-bw nests its messages over lines; the first and the line's text suffice.
                let first = e.lines().next().unwrap_or_default();
                let text = e
                    .split("String: '")
                    .nth(1)
                    .and_then(|t| t.split('\n').next());
                match text {
                    Some(t) => format!("`{name}`: PLY element `{}`: {first} (`{t}`)", element.name),
                    None => format!("`{name}`: PLY element `{}`: {first}", element.name),
                }
            }
        };
        match element.name.as_str() {
            "vertex" => {
                vertices = Some(
                    Parser::<PlyVertex>::new()
                        .read_payload_for_element(&mut reader, element, &header)
                        .map_err(err)?,
                )
            }
            "face" => {
                faces = Some(
                    Parser::<PlyFace>::new()
                        .read_payload_for_element(&mut reader, element, &header)
                        .map_err(err)?,
                )
            }
            _ => {
                Parser::<PlyOther>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(err)?;
            }
        }
    }
    if has_trailing_data(
        &mut reader,
        header.encoding == ply_rs_bw::ply::Encoding::Ascii,
    ) {
        return Err(format!(
            "`{name}`: there is data after the elements the header declares ({}): the header's counts disagree with the data",
            header
                .elements
                .values()
                .map(|e| format!("{} {}", e.count, e.name))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let vertices = vertices.ok_or(format!("`{name}` has no `vertex` element"))?;
    let faces = faces.ok_or(format!("`{name}` has no `face` element"))?;
    let mut mesh = Mesh::default();
    let first = vertices.first().map_or(0, |v| v.set);
    let (has_normals, has_uvs) = (first & 1 << 3 != 0, first & 1 << 6 != 0);
    mesh.positions.reserve_exact(vertices.len());
    for (i, v) in vertices.iter().enumerate() {
        if let Some(k) = (0..3).find(|&k| v.set & (1 << k) == 0) {
            return Err(format!(
                "`{name}`: vertex {i} lacks `{}`",
                ["x", "y", "z"][k]
            ));
        }
        mesh.positions.push(Vec3::new(v.c[0], v.c[1], v.c[2]));
        if has_normals {
            if let Some(k) = (3..6).find(|&k| v.set & (1 << k) == 0) {
                return Err(format!(
                    "`{name}`: vertex {i} lacks `{}`",
                    ["nx", "ny", "nz"][k - 3]
                ));
            }
            mesh.normals.push(Vec3::new(v.c[3], v.c[4], v.c[5]));
        }
        if has_uvs {
            mesh.uvs.push(Vec2::new(v.c[6], v.c[7]));
        }
    }
    drop(vertices);
    mesh.indices.reserve_exact(faces.len());
    for (f, face) in faces.iter().enumerate() {
        let idx = face
            .indices()
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
