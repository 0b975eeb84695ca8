//! PLY meshes (ASCII and binary), read with ply-rs-bw into compact per-vertex and per-face
//! records; polygons become triangle fans.

use super::Mesh;
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};
use std::path::Path;

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

pub(super) fn load_ply(path: &Path) -> Result<Mesh, String> {
    let name = path.display();
    let file = crate::io::input_file::open(path, crate::io::input_file::Kind::Mesh)?;
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
