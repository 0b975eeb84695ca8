//! OBJ meshes, read with tobj (triangulated, one index per vertex); an error names the line
//! tobj failed on, found by a scan of the file.

use super::Mesh;
use glam::{Vec2, Vec3};
use std::path::Path;

pub(super) fn load_obj(path: &Path) -> Result<Mesh, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let file = crate::io::input_file::open(path, crate::io::input_file::Kind::Mesh)?;
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
